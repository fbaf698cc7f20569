// An environment sequence's frames, decoded ahead of playback on a thread of their own, so
// that the frame thread never waits for a file: it takes a frame once it is ready, and the
// sky holds the last one meanwhile. Memory stays what `lookahead` frames take, however long
// the sequence is.
#pragma once

#include "staging_pool.hpp"

#include <skygraph/hdr_image.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/staging_buffer.hpp>

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace skygraph::app {

/// One decoded frame of a sequence, or why it could not be.
struct SequenceFrame {
    uint32_t index = 0;  ///< in the sequence: 0 <= index < count
    std::string file;
    HdrImage pixels;    ///< at the stream's size; empty when `error` is set or the frame is staged
    /// The pixels in host-visible memory (float RGBA, rows tightly packed), when the stream
    /// stages its frames; null otherwise or when `error` is set.
    std::shared_ptr<const StagingBuffer> staged;
    std::string error;  ///< the ImageError's message, naming the file
    double decodeMs = 0.0;  ///< reading, decoding, resampling and staging, on the stream's thread
};

class SequenceStream {
public:
    /// Starts decoding `sequence` from frame `first`. Frames of another size than `width` x
    /// `height` are resampled to it (resampleEquirect), so that a bake beside the frames can
    /// take them. At most `lookahead` (>= 1) decoded frames wait to be taken. With
    /// `stagingDevice` (borrowed; it must outlive the stream and the frames taken), each frame
    /// is also copied into a StagingBuffer on it, on the stream's thread, and handed out in
    /// `staged` instead of `pixels`: the frame thread then only passes the buffer on to the
    /// bake. A buffer is reused once nothing else holds it. Throws std::invalid_argument for a
    /// sequence of no frames.
    SequenceStream(EnvironmentSequence sequence, uint32_t width, uint32_t height, uint32_t first = 0,
                   uint32_t lookahead = 2, Device* stagingDevice = nullptr);
    /// Stops the thread; a decode under way is finished first.
    ~SequenceStream();
    SequenceStream(const SequenceStream&) = delete;
    SequenceStream& operator=(const SequenceStream&) = delete;

    /// The newest decoded frame of the `span` frames from `first` on (looping), moved out to
    /// the caller, and those decoded before it dropped; nullopt while none of them is. Then,
    /// when the thread is headed for frames before the range's last, it goes on (after the
    /// frame it decodes now) `ahead` frames past that one: playback asks for the frames whose
    /// time has come since the last one it took, and a decode that takes longer than a
    /// frame's time would otherwise never catch up.
    [[nodiscard]] std::optional<SequenceFrame> takeNewest(uint32_t first, uint32_t span, uint32_t ahead = 0);
    /// The last decode's time, 0 before the first.
    [[nodiscard]] double lastDecodeMs() const;

    [[nodiscard]] const EnvironmentSequence& sequence() const noexcept { return sequence_; }
    /// The decode times of the last frames decoded (failures included; at most 1024).
    [[nodiscard]] std::vector<double> decodeTimesMs() const;
    /// The most frames held at once, decoded and waiting, since the start.
    [[nodiscard]] size_t mostFramesHeld() const;
    /// The staging buffers made so far (0 without a staging device): the most frames staged
    /// at once, waiting, decoding or not yet copied by their bake.
    [[nodiscard]] size_t stagingBuffers() const;

private:
    void decodeLoop();

    /// Frames from `from` forwards to `to`, looping: 0 when they are the same.
    [[nodiscard]] uint32_t stepsFrom(uint32_t from, uint32_t to) const noexcept;

    const EnvironmentSequence sequence_;
    const uint32_t width_, height_;
    const size_t lookahead_;
    std::optional<StagingPool> staging_;  ///< with a staging device; the stream thread's alone
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<SequenceFrame> ready_;
    static constexpr size_t kDecodeTimesKept = 1024;
    uint32_t next_ = 0;  ///< the frame the thread decodes next
    bool stopping_ = false;
    std::vector<double> decodeMs_;
    size_t mostHeld_ = 0;
    size_t stagingMade_ = 0;
    std::thread thread_;  ///< last: started once everything it reads is
};

}  // namespace skygraph::app
