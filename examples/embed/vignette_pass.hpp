// The example's own pass type, registered next to skygraph's built-ins: both halves, the
// declaration the compiler checks graphs against and the recording code.
#pragma once

#include <skygraph/pass.hpp>

#include <memory>

namespace embed {

/// Slots "input" (Read@Fragment, sampled) and "output" (Write@ColorAttachment); params
/// {"strength": number in [0, 1]} (default 0.5).
[[nodiscard]] skygraph::PassTypeInfo vignettePassType();

/// Recording code for one VignettePass of a graph.
[[nodiscard]] std::unique_ptr<skygraph::PassImplementation> makeVignettePass(const skygraph::PassDesc& desc);

/// What the shader computes for the pixel centre (x, y) of a width x height target, for checks.
[[nodiscard]] double vignetteFactor(double strength, uint32_t x, uint32_t y, uint32_t width, uint32_t height);

}  // namespace embed
