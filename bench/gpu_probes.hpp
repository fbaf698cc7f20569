// Hand-written GPU measurements beside the framework's frames (gpu_frame_bench): the
// device's memory bandwidth, and a compute-shader tonemapper that shows what the
// TonemappingPass's work costs off the fragment path. Bench-only.
#pragma once

#include <skygraph/executor.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace skygraph::gpubench {

/// Median GPU times of one measured operation over its repetitions.
struct ProbeResult {
    std::string name;       ///< e.g. "copy_buffer", "tonemap_compute_8x8"
    double bytes = 0;       ///< Bytes the operation must read plus write.
    double medianMs = 0;
    double p10Ms = 0;
    double p90Ms = 0;
    uint32_t repetitions = 0;
    [[nodiscard]] double gigabytesPerSecond() const { return medianMs > 0 ? bytes / (medianMs * 1e6) : 0; }
};

/// DRAM bandwidth: vkCmdCopyBuffer and a compute copy (16-byte loads and stores) of a
/// `bytes`-sized device-local buffer that a compute shader first filled with a hash (never
/// zeros), `repetitions` times each. Bytes counted: read plus written (2 x `bytes`).
[[nodiscard]] std::vector<ProbeResult> measureBandwidth(Device& device, uint64_t bytes, uint32_t repetitions);

/// The TonemappingPass's operation (common/tonemap.glsl, ACES Narkowicz, sRGB encode) as a
/// compute shader: an RGBA16F image of `width` x `height` (filled with a hash pattern) read
/// once, an RGBA8 storage image written once, for each workgroup shape. Bytes: 8 + 4 per pixel.
[[nodiscard]] std::vector<ProbeResult> measureComputeTonemap(Device& device, uint32_t width, uint32_t height,
                                                             uint32_t repetitions);

}  // namespace skygraph::gpubench
