// SkyboxPass's declaration: its slots, params and usage checks (recording code: skybox_pass.cpp).
#include "builtin_pass_types.hpp"
#include "param_rules.hpp"
#include "skybox_rules.hpp"

namespace skygraph::passes {

PassTypeInfo skyboxPassType() {
    const auto checkEnvironment = [](const PassDesc& pass, const GraphDesc& graph) {
        const ResourceDesc *environment = nullptr, *previous = nullptr;
        size_t environmentUsage = 0, previousUsage = 0;
        for (size_t i = 0; i < pass.uses.size(); ++i) {
            const std::string_view slot = graph.slotName(pass.uses[i].slot);
            if (slot == "environment") {
                environment = &graph.resources[pass.uses[i].resource];
                environmentUsage = i;
            }
            if (slot == "previous") {
                previous = &graph.resources[pass.uses[i].resource];
                previousUsage = i;
            }
        }
        std::vector<UsageError> problems;
        if (auto problem = skyboxFadeProblem(environment, previous)) problems.push_back({previousUsage, std::move(*problem)});
        // Without an environment the sky is procedural, and `sampling` has nothing to state.
        const auto sampling = pass.params.json().find("sampling");
        if (environment && sampling != pass.params.json().end() && sampling->is_string())
            if (auto problem = skyboxSamplingProblem(*environment, sampling->get<std::string>()))
                problems.push_back({environmentUsage, std::move(*problem)});
        return problems;
    };
    return {"SkyboxPass",
            {slot("depth", Stage::DepthAttachment, {Access::Read}, BindAs::Default,
                  "rejects covered pixels (GREATER_OR_EQUAL)"),
             slot("color", Stage::ColorAttachment, {Access::ReadWrite}, BindAs::Default,
                  "HDR target; sky fills uncovered pixels"),
             ofTypes(slot("environment", Stage::Fragment, {Access::Read}, BindAs::Sampled,
                          "cubemap or equirect environment", true),
                     {ResourceType::Cube, ResourceType::Image2D}),
             byNameOnly(ofTypes(
                 slot("previous", Stage::Fragment, {Access::Read}, BindAs::Sampled,
                      "cubemap the sky fades from to `environment` (SkyFade): a sequence's previous frame", true),
                 {ResourceType::Cube}))},
            false,
            rules({{"sampling", oneOf({"cubemap", "equirect"})},
                   {"rotation_deg", numberIn(-360.0, 360.0)},
                   {"output", oneOf({"radiance", "direction"})}}),
            "Fullscreen-triangle sky at the reverse-Z far plane.",
            {},
            checkEnvironment};
}

}  // namespace skygraph::passes
