// UploadPass's declaration: one slot, written by a copy (recording code: upload_pass.cpp).
#include "builtin_pass_types.hpp"
#include "param_rules.hpp"
#include "upload_rules.hpp"

namespace skygraph::passes {

PassTypeInfo uploadPassType() {
    const auto checkTarget = [](const PassDesc& pass, const GraphDesc& graph) {
        std::vector<UsageError> problems;
        for (size_t i = 0; i < pass.uses.size(); ++i)
            if (auto problem = uploadTargetProblem(graph.resources[pass.uses[i].resource], pass.uses[i].usage.range))
                problems.push_back({i, std::move(*problem)});
        return problems;
    };
    return {"UploadPass",
            {slot("target", Stage::Transfer, {Access::Write}, BindAs::Default,
                  "mip 0 of every layer of an image, or a whole buffer")},
            false, rules({}),
            "Copies the pixels the application staged for this frame (Renderer::stageUpload) into `target`. "
            "A copy runs on any queue: on the transfer queue it overlaps the other queues' work.",
            {}, checkTarget};
}

}  // namespace skygraph::passes
