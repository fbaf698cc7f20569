// ForwardPass's declaration: its slots, params and usage checks (recording code: forward_pass.cpp).
#include "builtin_pass_types.hpp"
#include "param_rules.hpp"

#include <skygraph/plan.hpp>

namespace skygraph::passes {

PassTypeInfo forwardPassType() {
    // The pipeline tests GREATER against what the depth attachment starts with. A Write loads
    // nothing (DONT_CARE), so only a load-op clear gives it a start: the resource's `clear`,
    // applied by the load op when the usage covers the whole image (a part of it is cleared by a
    // Clear step, which the Write then discards). Otherwise every fragment meets undefined depth.
    const auto checkDepthStart = [](const PassDesc& pass, const GraphDesc& graph) {
        std::vector<UsageError> problems;
        for (size_t i = 0; i < pass.uses.size(); ++i) {
            const UsageDecl& use = pass.uses[i];
            const ResourceDesc& depth = graph.resources[use.resource];
            if (graph.slotName(use.slot) != "depth" || use.usage.access != Access::Write) continue;
            if (!depth.clear) {
                problems.push_back({i, "ForwardPass tests depth against what slot 'depth' starts with, and a Write "
                                       "of '" + depth.name + "', which has no `clear`, starts with undefined values: "
                                       "add \"clear\": { \"depth\": 0.0 } (reverse-Z's far plane) to '" +
                                           depth.name + "', or use ReadWrite after an earlier depth pass"});
                continue;
            }
            // An attachment renders to one level, so a range of a full chain ("mips": 0, whose
            // length waits for the output size) is a part of it but at a 1x1 output.
            const std::optional<SubresourceRange>& range = use.usage.range;
            if (range && (range->baseMip != 0 || range->baseLayer != 0 || range->layerCount < depth.layers ||
                          range->mipCount != depth.mips))
                problems.push_back({i, "ForwardPass tests depth against what slot 'depth' starts with, and a Write of "
                                       "part of '" + depth.name + "' discards it: only a Write of the whole image "
                                       "starts from its `clear` (the load op's); write all of it, or use ReadWrite"});
        }
        return problems;
    };
    // Which pass uses the resource first depends on the features, so a Write after another
    // pass's use (two depth passes that both run) shows only in the plan: its load op there is
    // not the clear's.
    const auto checkDepthStartInPlan = [](const PlannedPass& pass, const Plan&) {
        std::vector<UsageError> problems;
        for (size_t i = 0; i < pass.usages.size(); ++i) {
            const PlannedUsage& use = pass.usages[i];
            if (use.slot != "depth" || use.usage.access != Access::Write || use.load == LoadOp::Clear) continue;
            problems.push_back({i, "ForwardPass tests depth against what slot 'depth' starts with, and this Write is "
                                   "not the first use of the resource in the plan (a pass before it that runs uses "
                                   "it), so it discards what that pass left and does not start from the clear either: "
                                   "use ReadWrite to test against what that pass left, or let only one of them run"});
        }
        return problems;
    };
    return {"ForwardPass",
            {slot("color", Stage::ColorAttachment, {Access::Write, Access::ReadWrite}, BindAs::Default,
                  "HDR target the objects shade into"),
             slot("depth", Stage::DepthAttachment, {Access::Write, Access::ReadWrite}, BindAs::Default,
                  "reverse-Z depth: a Write starts from the resource's `clear` (0, the far plane), a ReadWrite "
                  "from an earlier pass's depth"),
             ofTypes(slot("environment", Stage::Fragment, {Access::Read}, BindAs::Sampled, "environment cubemap", true),
                     {ResourceType::Cube}),
             ofTypes(slot("irradiance", Stage::Fragment, {Access::Read}, BindAs::Sampled, "diffuse IBL", true),
                     {ResourceType::Cube}),
             ofTypes(slot("prefiltered", Stage::Fragment, {Access::Read}, BindAs::Sampled,
                          "specular IBL, one roughness per mip", true),
                     {ResourceType::Cube}),
             ofTypes(slot("brdf_lut", Stage::Fragment, {Access::Read}, BindAs::Sampled, "split-sum BRDF table", true),
                     {ResourceType::Image2D})},
            false,
            // No params: the debug view is the scene's (Scene::debugView), which also makes the
            // tonemapper a passthrough.
            rules({}),
            "Metal/rough GGX shading of the scene's objects.",
            {},
            checkDepthStart,
            checkDepthStartInPlan};
}

}  // namespace skygraph::passes
