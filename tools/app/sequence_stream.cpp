// SequenceStream: see sequence_stream.hpp.
#include "sequence_stream.hpp"

#include "equirect_resample.hpp"

#include <algorithm>
#include <chrono>
#include <exception>

namespace skygraph::app {

SequenceStream::SequenceStream(EnvironmentSequence sequence, uint32_t width, uint32_t height, uint32_t first,
                               uint32_t lookahead)
    : sequence_(std::move(sequence)),
      width_(width),
      height_(height),
      lookahead_(std::max<uint32_t>(lookahead, 1)),
      next_(first % std::max<uint32_t>(sequence_.count, 1)),
      thread_([this] { decodeLoop(); }) {}

SequenceStream::~SequenceStream() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

uint32_t SequenceStream::stepsFrom(uint32_t from, uint32_t to) const noexcept {
    return (to + sequence_.count - from) % sequence_.count;
}

std::optional<SequenceFrame> SequenceStream::take(uint32_t index) {
    std::unique_lock lock(mutex_);
    const auto queued = std::find_if(ready_.begin(), ready_.end(), [&](const SequenceFrame& f) { return f.index == index; });
    if (queued != ready_.end()) {
        SequenceFrame frame = std::move(*queued);
        ready_.erase(ready_.begin(), queued + 1);  // those before it were skipped
        lock.unlock();
        wake_.notify_all();
        return frame;
    }
    // Frames that playback will not ask for before it loops round: all but the few after `index`.
    const size_t before = ready_.size();
    std::erase_if(ready_, [&](const SequenceFrame& f) { return stepsFrom(index, f.index) >= lookahead_; });
    // `index` is not decoded. Unless frames after it are queued (it was skipped) or the thread
    // is decoding it or about to, the thread is behind: it skips to `index`.
    const bool decodingIt = stepsFrom(index, next_) == 1;
    const bool skip = ready_.empty() && !decodingIt && next_ != index;
    if (skip) {
        next_ = index;
        ++generation_;
    }
    const bool room = ready_.size() != before;
    lock.unlock();
    if (skip || room) wake_.notify_all();
    return std::nullopt;
}

void SequenceStream::decodeLoop() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return stopping_ || ready_.size() < lookahead_; });
        if (stopping_) return;
        const uint32_t index = next_;
        const uint64_t generation = generation_;
        next_ = (index + 1) % sequence_.count;
        lock.unlock();
        SequenceFrame frame;
        frame.index = index;
        frame.file = sequence_.frame(index).string();
        const auto start = std::chrono::steady_clock::now();
        try {
            frame.pixels = loadHdrImage(frame.file);
            if (frame.pixels.width != width_ || frame.pixels.height != height_)
                frame.pixels = resampleEquirect(frame.pixels, width_, height_);
        } catch (const std::exception& e) {
            frame.pixels = {};
            frame.error = e.what();
        }
        frame.decodeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        lock.lock();
        decodeMs_.push_back(frame.decodeMs);
        if (generation != generation_) continue;  // playback skipped past it while it decoded
        ready_.push_back(std::move(frame));
        mostHeld_ = std::max(mostHeld_, ready_.size());
    }
}

std::vector<double> SequenceStream::decodeTimesMs() const {
    std::lock_guard lock(mutex_);
    return decodeMs_;
}

size_t SequenceStream::mostFramesHeld() const {
    std::lock_guard lock(mutex_);
    return mostHeld_;
}

}  // namespace skygraph::app
