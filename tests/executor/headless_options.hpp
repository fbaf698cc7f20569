// Compile options for running a graph headless in tests and tools: no swapchain, so the
// Present target is left in TransferSrc and copied to the host instead of presented.
#pragma once

#include <skygraph/compiler.hpp>
#include <skygraph/graph.hpp>

#include <cstdint>
#include <set>
#include <string>

namespace skygraph::test {

/// Options for an output of width x height (the tests' renders are small).
inline CompileOptions sizedOptions(uint32_t width = 16, uint32_t height = 16) {
    CompileOptions o;
    o.outputWidth = width;
    o.outputHeight = height;
    return o;
}

/// `co` made headless: every `final: Present` becomes TransferSrc, and each Present target
/// that the plan uses (a graph may declare one per feature combination) is read back after
/// every frame. Throws GraphError as compile() does.
inline CompileOptions headless(const GraphDesc& graph, CompileOptions co = sizedOptions()) {
    co.presentReplacement = ExternalState::TransferSrc;
    const Plan plan = compile(graph, co);
    for (const ResourceDesc& r : graph.resources)
        if (r.final == ExternalState::Present && plan.resourceIndex(r.name) >= 0) co.readbacks.insert(r.name);
    return co;
}

}  // namespace skygraph::test
