// SequenceStream: see sequence_stream.hpp.
#include "sequence_stream.hpp"

#include "environment_bake.hpp"
#include "equirect_resample.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <utility>

namespace skygraph::app {

SequenceStream::SequenceStream(EnvironmentSequence sequence, uint32_t width, uint32_t height, uint32_t first,
                               uint32_t lookahead, Device* stagingDevice)
    : sequence_(std::move(sequence)),
      width_(width),
      height_(height),
      lookahead_(std::max<uint32_t>(lookahead, 1)),
      next_(first % std::max<uint32_t>(sequence_.count, 1)),
      thread_() {
    if (sequence_.count == 0) throw std::invalid_argument("SequenceStream: a sequence of no frames");
    if (stagingDevice) staging_.emplace(*stagingDevice, rgba32fBytes(width, height));
    thread_ = std::thread([this] { decodeLoop(); });
}

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

std::optional<SequenceFrame> SequenceStream::takeNewest(uint32_t first, uint32_t span, uint32_t ahead) {
    span = std::clamp<uint32_t>(span, 1, sequence_.count);
    const uint32_t due = uint32_t((uint64_t(first) + span - 1) % sequence_.count);
    const auto inRange = [&](uint32_t index) { return stepsFrom(first, index) < span; };
    // Frames in the range before its last, the frame due: playback is past them.
    const auto passed = [&](uint32_t index) { return stepsFrom(first, index) + 1 < span; };
    // The range's last frame and the few after it, which playback asks for next.
    const uint64_t window = uint64_t(span) + lookahead_ + ahead;
    const auto coming = [&](uint32_t index) { return stepsFrom(first, index) < window && !passed(index); };
    std::unique_lock lock(mutex_);
    std::optional<SequenceFrame> taken;
    auto newest = ready_.end();
    for (auto it = ready_.begin(); it != ready_.end(); ++it)
        if (inRange(it->index)) newest = it;
    if (newest != ready_.end()) {
        taken = std::move(*newest);
        ready_.erase(ready_.begin(), newest + 1);  // older than the frame taken: never shown
    }
    const size_t before = ready_.size();
    std::erase_if(ready_, [&](const SequenceFrame& f) { return !coming(f.index); });
    // A thread headed for frames playback is past falls behind for good when decoding is
    // slower than the frames' pace: after the frame it decodes now (which is finished, so that
    // a slow decode still shows something), it goes on `ahead` frames past the frame due,
    // where playback will be once that one is decoded.
    const bool skip = !coming(next_);
    if (skip) next_ = uint32_t((uint64_t(due) + ahead) % sequence_.count);
    const bool wake = skip || taken || ready_.size() != before;
    lock.unlock();
    if (wake) wake_.notify_all();
    return taken;
}

double SequenceStream::lastDecodeMs() const {
    std::lock_guard lock(mutex_);
    return decodeMs_.empty() ? 0.0 : decodeMs_.back();
}

void SequenceStream::decodeLoop() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return stopping_ || ready_.size() < lookahead_; });
        if (stopping_) return;
        const uint32_t index = next_;
        next_ = (index + 1) % sequence_.count;
        lock.unlock();
        SequenceFrame frame;
        frame.index = index;
        const auto start = std::chrono::steady_clock::now();
        try {  // anything thrown here would end the program: it becomes the frame's error
            frame.file = sequence_.frame(index).string();
            frame.pixels = loadEnvironmentImage(frame.file);
            if (frame.pixels.width != width_ || frame.pixels.height != height_)
                frame.pixels = resampleEquirect(frame.pixels, width_, height_);
            if (staging_) frame.staged = staging_->stage(std::exchange(frame.pixels, {}).rgba);
        } catch (const std::exception& e) {
            frame.pixels = {};
            frame.staged.reset();
            frame.error = e.what();
        }
        frame.decodeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        lock.lock();
        if (staging_) stagingMade_ = staging_->size();
        if (decodeMs_.size() == kDecodeTimesKept) decodeMs_.erase(decodeMs_.begin());
        decodeMs_.push_back(frame.decodeMs);
        ready_.push_back(std::move(frame));
        mostHeld_ = std::max(mostHeld_, ready_.size());
    }
}

size_t SequenceStream::stagingBuffers() const {
    std::lock_guard lock(mutex_);
    return stagingMade_;
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
