// The declarations of TonemappingPass and TonemappingComputePass: their slots and params
// (recording code: tonemapping_pass.cpp).
#include "builtin_pass_types.hpp"
#include "param_rules.hpp"
#include "tonemapping_rules.hpp"

#include <string>

namespace skygraph::passes {

PassTypeInfo tonemappingPassType() {
    return {"TonemappingPass",
            {ofTypes(slot("hdr", Stage::Fragment, {Access::Read}, BindAs::Sampled, "HDR input"),
                     {ResourceType::Image2D}),
             slot("output", Stage::ColorAttachment, {Access::Write}, BindAs::Default, "display-referred output")},
            false,
            rules({{"operator", oneOf({"aces_narkowicz", "aces_hill", "khronos_pbr_neutral", "passthrough"})},
                   {"exposure_ev", numberIn(-64.0, 64.0)}}),
            "Exposure (2^EV), a tone curve, and sRGB encoding from the output format."};
}

PassTypeInfo tonemappingComputePassType() {
    const auto checkOutput = [](const PassDesc& pass, const GraphDesc& graph) {
        std::vector<UsageError> problems;
        for (size_t i = 0; i < pass.uses.size(); ++i) {
            const ResourceDesc& r = graph.resources[pass.uses[i].resource];
            if (graph.slotName(pass.uses[i].slot) == "output" && !tonemappingComputeWrites(r.format.format))
                problems.push_back({i, tonemappingComputeOutputProblem(r.format.name)});
        }
        return problems;
    };
    return {"TonemappingComputePass",
            {ofTypes(slot("hdr", Stage::Compute, {Access::Read}, BindAs::Sampled, "HDR input"),
                     {ResourceType::Image2D}),
             ofTypes(slot("output", Stage::Compute, {Access::Write}, BindAs::Storage,
                          std::string("display-referred output, sRGB-encoded by the shader: ") +
                              tonemappingComputeOutputNames()),
                     {ResourceType::Image2D})},
            false,
            rules({{"operator", oneOf({"aces_narkowicz", "aces_hill", "khronos_pbr_neutral", "passthrough"})},
                   {"exposure_ev", numberIn(-64.0, 64.0)}}),
            "TonemappingPass as a compute shader (same math), writing a storage image with sRGB encoded by the shader.",
            {},
            checkOutput};
}

}  // namespace skygraph::passes
