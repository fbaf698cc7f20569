// A bench-only compute version of the TonemappingPass, registered into gpu_frame_bench's pass
// library as "BenchComputeTonemapPass", and the graph variants that use it. It measures what
// the built-in pass would cost off the fragment path, through the real compiler and Renderer
// (plan barriers, lastTimings); it is not a built-in pass.
#pragma once

#include <skygraph/pass.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace skygraph::gpubench {

/// Registers "BenchComputeTonemapPass": slots hdr (Read@Compute, sampled) and output
/// (Write@Compute, storage, R8G8B8A8_UNORM), the same tone curves and sRGB encoding as
/// TonemappingPass (shaders/common/tonemap.glsl), 2x2 pixels per invocation in 8x8 groups.
void addComputeTonemapPass(PassLibrary& library);

/// Rewrites a graph file's JSON for a named variant; throws std::invalid_argument for an
/// unknown name or a graph without the expected "swapchain" / TonemappingPass:
///   "unorm-swapchain": the swapchain is B8G8R8A8_UNORM (the pass encodes sRGB in the shader);
///   "compute-tonemap": the swapchain is R8G8B8A8_UNORM and every TonemappingPass becomes a
///                      BenchComputeTonemapPass reading Read@Compute, writing Write@Compute.
[[nodiscard]] nlohmann::json graphVariant(nlohmann::json graph, const std::string& variant);

}  // namespace skygraph::gpubench
