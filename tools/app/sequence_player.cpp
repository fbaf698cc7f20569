// SequencePlayer: see sequence_player.hpp.
#include "sequence_player.hpp"

#include <cmath>

namespace skygraph::app {

SequencePlayer::SequencePlayer(EnvironmentSequence sequence, uint32_t width, uint32_t height)
    : fps_(sequence.fps), count_(sequence.count) {
    stream_ = std::make_unique<SequenceStream>(std::move(sequence), width, height, 1);
    stats_.shown = 1;
    stats_.current = 0;
}

int64_t SequencePlayer::tick(double seconds) const noexcept {
    return int64_t(std::floor(std::max(seconds, 0.0) * fps_));
}

std::optional<SequenceFrame> SequencePlayer::frameToBake(double seconds) {
    const int64_t due = tick(seconds);
    if (due <= lastStarted_) return std::nullopt;  // started already; it holds until the next is due
    std::optional<SequenceFrame> frame = stream_->take(uint32_t(due % count_));
    if (!frame) return std::nullopt;  // not decoded yet: the sky holds the last frame
    // Every tick between the last frame started and this one passed unshown.
    stats_.dropped += uint32_t(due - lastStarted_ - 1);
    lastStarted_ = due;
    if (!frame->error.empty()) {
        ++stats_.dropped;
        ++stats_.failed;
    } else {
        baking_ = due;
    }
    return frame;
}

void SequencePlayer::swappedIn(double seconds) {
    if (baking_ < 0) return;
    ++stats_.shown;
    if (tick(seconds) > baking_) ++stats_.late;
    stats_.current = uint32_t(baking_ % count_);
    baking_ = -1;
}

}  // namespace skygraph::app
