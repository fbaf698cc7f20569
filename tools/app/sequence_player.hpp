// When an environment sequence's frames are due, and what became of each: shown on time,
// shown late, or dropped. The sky never goes black: until a due frame is baked and swapped
// in, the frames hold the last one.
#pragma once

#include "sequence_stream.hpp"

#include <cstdint>
#include <memory>
#include <optional>

namespace skygraph::app {

/// What playback has done so far.
struct SequenceStats {
    uint32_t shown = 0;    ///< frames swapped in
    uint32_t late = 0;     ///< of those, swapped in after their time had passed
    uint32_t dropped = 0;  ///< frames never shown: their time passed first, or they failed (counted
                           ///< once a later frame is taken)
    uint32_t failed = 0;   ///< of the dropped, frames that could not be decoded or baked
    std::optional<uint32_t> current;  ///< the frame the sky shows, once one was swapped in
};

/// Where playback stands: what a player that takes over from another (after a rebuild) goes on from.
struct SequencePosition {
    int64_t tick = 0;  ///< playback's frame number (SequencePlayer::tick) of the frame on screen
    /// The last frame handed out: past `tick` when later ones failed or were dropped, which
    /// are counted in `stats` already.
    int64_t lastStarted = 0;
    SequenceStats stats;
};

class SequencePlayer {
public:
    /// Streams `sequence` (SequenceStream) at `width` x `height`, the running equirect's size,
    /// staged on `stagingDevice` when given (SequenceStream). The frame of `from` (frame 0 when
    /// there is none) is on screen already: the environment was baked from it. With `from`,
    /// playback goes on where it stood, its stats too.
    SequencePlayer(EnvironmentSequence sequence, uint32_t width, uint32_t height, Device* stagingDevice = nullptr,
                   std::optional<SequencePosition> from = std::nullopt);
    SequencePlayer(const SequencePlayer&) = delete;
    SequencePlayer& operator=(const SequencePlayer&) = delete;

    /// At `seconds` of playback: nullopt while the frame it last returned is being baked (until
    /// swappedIn() or bakeFailed()); else the frame to bake now, the newest decoded one whose
    /// time has come since the last frame started (the frame due, when decoding keeps pace);
    /// nullopt while none is decoded. The frames passed over are counted dropped. A frame that failed to decode is returned too (its `error` set,
    /// counted dropped), for the caller to report; bake it not.
    [[nodiscard]] std::optional<SequenceFrame> frameToBake(double seconds);
    /// The frame frameToBake() last returned without an error is on screen since `seconds`.
    void swappedIn(double seconds);
    /// Its bake could not start: it is counted dropped and failed.
    void bakeFailed();
    /// Where playback stands, for a player that goes on from here. A frame being baked counts
    /// as on screen (shown): whoever goes on bakes it into the environment it starts with.
    [[nodiscard]] SequencePosition position() const noexcept;

    [[nodiscard]] const SequenceStats& stats() const noexcept { return stats_; }
    [[nodiscard]] double fps() const noexcept { return fps_; }
    [[nodiscard]] const SequenceStream& stream() const noexcept { return *stream_; }
    /// Playback's frame number at `seconds`: it counts on past the end as playback loops.
    [[nodiscard]] int64_t tick(double seconds) const noexcept;

private:
    std::unique_ptr<SequenceStream> stream_;
    double fps_;
    uint32_t count_;
    SequenceStats stats_;
    int64_t lastStarted_ = 0;   ///< the tick of the last frame handed out
    int64_t baking_ = -1;       ///< the tick of the frame being baked, or -1
    int64_t onScreen_ = 0;      ///< the tick of the frame on screen
};

}  // namespace skygraph::app
