// The declarations of TonemappingPass and TonemappingComputePass: their slots and params
// (recording code: tonemapping_pass.cpp).
#include "builtin_pass_types.hpp"
#include "param_rules.hpp"

namespace skygraph::passes {

PassTypeInfo tonemappingPassType() {
    return {"TonemappingPass",
            {slot("hdr", Stage::Fragment, {Access::Read}, BindAs::Sampled, "HDR input"),
             slot("output", Stage::ColorAttachment, {Access::Write}, BindAs::Default, "display-referred output")},
            false,
            rules({{"operator", oneOf({"aces_narkowicz", "aces_hill", "khronos_pbr_neutral", "passthrough"})},
                   {"exposure_ev", numberIn(-64.0, 64.0)}}),
            "Exposure (2^EV), a tone curve, and sRGB encoding from the output format."};
}

PassTypeInfo tonemappingComputePassType() {
    return {"TonemappingComputePass",
            {slot("hdr", Stage::Compute, {Access::Read}, BindAs::Sampled, "HDR input"),
             slot("output", Stage::Compute, {Access::Write}, BindAs::Storage,
                  "display-referred output: R8G8B8A8_UNORM, B8G8R8A8_UNORM (or a float format), sRGB-encoded by the shader")},
            false,
            rules({{"operator", oneOf({"aces_narkowicz", "aces_hill", "khronos_pbr_neutral", "passthrough"})},
                   {"exposure_ev", numberIn(-64.0, 64.0)}}),
            "TonemappingPass as a compute shader (same math), writing a storage image with sRGB encoded by the shader."};
}

}  // namespace skygraph::passes
