// Generic: performs every declared access for real. Its recording code, which a renderer also
// runs for every pass type without recording code of its own: generic_pass.cpp.
#include "builtin_pass_types.hpp"

#include <skygraph/graph.hpp>

#include <string>
#include <vector>

namespace skygraph::passes {
namespace {

/// What Generic's recording code needs of a pass's buffers, found where the file says them:
/// it draws one triangle (3 indices of 4 bytes, or the 20 bytes of an indexed indirect draw)
/// and reads or writes a word of every buffer a shader binds.
std::vector<UsageError> checkGenericUsages(const PassDesc& pass, const GraphDesc& graph) {
    std::vector<UsageError> problems;
    int indexBuffer = -1, indirectBuffer = -1;
    for (size_t i = 0; i < pass.uses.size(); ++i) {
        const Usage& u = pass.uses[i].usage;
        const ResourceDesc& r = graph.resources[pass.uses[i].resource];
        if (r.isImage()) continue;
        const auto tooSmall = [&](uint64_t least, const std::string& as) {
            if (r.sizeBytes < least)
                problems.push_back({i, "Generic reads " + std::to_string(least) + " bytes of " + as + ", and '" + r.name +
                                           "' has " + std::to_string(r.sizeBytes)});
        };
        if (u.stage == Stage::VertexInput && u.as == BindAs::Index) {
            if (indexBuffer >= 0)
                problems.push_back({i, "a pass draws with one index buffer, and '" +
                                           graph.resources[pass.uses[size_t(indexBuffer)].resource].name +
                                           "' is already this pass's index buffer"});
            indexBuffer = static_cast<int>(i);
            tooSmall(12, "an index buffer (3 indices)");
        } else if (u.stage == Stage::Indirect) {
            if (indirectBuffer >= 0)
                problems.push_back({i, "a pass draws with one indirect buffer, and '" +
                                           graph.resources[pass.uses[size_t(indirectBuffer)].resource].name +
                                           "' is already this pass's indirect buffer"});
            indirectBuffer = static_cast<int>(i);
            tooSmall(20, "an indirect buffer (one indexed draw)");
        } else if (isShaderStage(u.stage)) {
            tooSmall(4, "a buffer a shader binds");
        }
    }
    return problems;
}

}  // namespace

PassTypeInfo genericPassType() {
    return {"Generic", {}, true, {}, "Performs every declared access for real; for tests and random graphs.", {},
            checkGenericUsages};
}

}  // namespace skygraph::passes
