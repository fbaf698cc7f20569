// SequencePlayer: see sequence_player.hpp.
#include "sequence_player.hpp"

#include <algorithm>
#include <cmath>

namespace skygraph::app {

SequencePlayer::SequencePlayer(EnvironmentSequence sequence, uint32_t width, uint32_t height, Device* stagingDevice,
                               std::optional<SequencePosition> from)
    : fps_(sequence.fps), count_(sequence.count) {
    if (from) {
        stats_ = from->stats;
        onScreen_ = std::max<int64_t>(from->tick, 0);
        lastStarted_ = std::max(from->lastStarted, onScreen_);
    } else {
        stats_.shown = 1;
    }
    stats_.current = uint32_t(onScreen_ % count_);
    stream_ = std::make_unique<SequenceStream>(std::move(sequence), width, height,
                                               uint32_t((lastStarted_ + 1) % count_), 2, stagingDevice);
}

SequencePosition SequencePlayer::position() const noexcept {
    if (baking_ < 0) return {onScreen_, lastStarted_, stats_};
    SequencePosition at{baking_, lastStarted_, stats_};
    ++at.stats.shown;
    at.stats.current = uint32_t(baking_ % count_);
    return at;
}

int64_t SequencePlayer::tick(double seconds) const noexcept {
    return int64_t(std::floor(std::max(seconds, 0.0) * fps_));
}

std::optional<SequenceFrame> SequencePlayer::frameToBake(double seconds) {
    if (baking_ >= 0) return std::nullopt;  // one bake at a time: the frame taken is still on its way
    const int64_t due = tick(seconds);
    if (due <= lastStarted_) return std::nullopt;  // started already; it holds until the next is due
    // Any frame whose time has come since the last one started will do, the newest best: when
    // decoding is slower than the frames' pace, the frame due has moved on by the time it is
    // decoded. At most one loop of the sequence back.
    const auto span = uint32_t(std::min<int64_t>(due - lastStarted_, count_));
    const int64_t first = due - span + 1;
    // Where playback will be once the thread has decoded a frame it skips to.
    // (Rounded: a decode well inside one frame's time aims at the frame due itself.)
    const auto ahead = uint32_t(std::min<double>(std::round(stream_->lastDecodeMs() * fps_ / 1000.0), count_ - 1));
    std::optional<SequenceFrame> frame = stream_->takeNewest(uint32_t(first % count_), span, ahead);
    if (!frame) return std::nullopt;  // not decoded yet: the sky holds the last frame
    const int64_t taken = first + (frame->index + count_ - uint32_t(first % count_)) % count_;
    // Every tick between the last frame started and this one passed unshown.
    stats_.dropped += uint32_t(taken - lastStarted_ - 1);
    lastStarted_ = taken;
    if (!frame->error.empty()) {
        ++stats_.dropped;
        ++stats_.failed;
    } else {
        baking_ = taken;
    }
    return frame;
}

void SequencePlayer::bakeFailed() {
    if (baking_ < 0) return;
    ++stats_.dropped;
    ++stats_.failed;
    baking_ = -1;
}

void SequencePlayer::swappedIn(double seconds) {
    if (baking_ < 0) return;
    ++stats_.shown;
    if (tick(seconds) > baking_) ++stats_.late;
    stats_.current = uint32_t(baking_ % count_);
    onScreen_ = baking_;
    baking_ = -1;
}

}  // namespace skygraph::app
