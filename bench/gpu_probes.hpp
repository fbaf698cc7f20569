// Hand-written GPU measurements beside the framework's frames (gpu_frame_bench): the
// device's memory bandwidth, and a compute-shader tonemapper that shows what the
// TonemappingPass's work costs off the fragment path. Bench-only.
#pragma once

#include <skygraph/device.hpp>

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
/// once, an RGBA8 storage image written once, for several workgroup shapes, load paths
/// (sampler texelFetch or imageLoad) and pixels per invocation. Bytes: 8 + 4 per pixel. Each
/// repetition first reads a 256 MiB buffer (untimed; 5x the H100's L2), so the input comes from
/// DRAM, not L2.
/// The first result, "empty_dispatch", is one empty workgroup: the fixed cost of a dispatch
/// between two timestamps.
/// `evictBytes`: the size of that buffer (smaller only for quick checks on a CPU device).
[[nodiscard]] std::vector<ProbeResult> measureComputeTonemap(Device& device, uint32_t width, uint32_t height,
                                                             uint32_t repetitions, uint64_t evictBytes = 256ull << 20);

/// The fragment path alone: a fullscreen triangle writing a constant to an RGBA8 attachment of
/// `width` x `height` (load DONT_CARE, store STORE). Bytes: 4 per pixel.
[[nodiscard]] ProbeResult measureFragmentFill(Device& device, uint32_t width, uint32_t height, uint32_t repetitions);

}  // namespace skygraph::gpubench
