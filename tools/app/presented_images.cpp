#include "presented_images.hpp"

namespace skygraph::app {

std::string presentsNothing(const Plan& plan, const GraphDesc& graph) {
    if (!plan.presentations().empty()) return {};
    std::string declared;
    for (const ResourceDesc& r : graph.resources)
        if (r.final == ExternalState::Present) declared += (declared.empty() ? "'" : ", '") + r.name + "'";
    if (declared.empty()) return {};
    return "no pass that runs in this combination uses a presented image (" + declared +
           "): the frame presents nothing";
}

}  // namespace skygraph::app
