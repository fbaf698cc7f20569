// Every shipped graph (graphs/*.json), under every feature combination, runs 3 frames with 2
// in flight on the validated device with zero messages. Every pass runs as Generic
// (genericPasses()): it performs exactly the accesses it declares.
#include "executor_test_util.hpp"
#include "shipped_cases.hpp"

#include <algorithm>
#include <optional>

namespace skygraph::test {
namespace {

class ShippedGraph : public ExecutorTest, public ::testing::WithParamInterface<GraphCase> {};

TEST_P(ShippedGraph, RunsThreeFramesCleanly) {
    const GraphCase& gc = GetParam();
    const auto registry = PassRegistry::withBuiltins();
    const GraphDesc graph = loadGraphFile(gc.file, registry);
    CompileOptions o = sizedOptions();
    o.features = gc.features;
    std::optional<CompiledGraph> compiled;
    try {
        compiled.emplace(graph, headless(graph, o));
    } catch (const GraphError& e) {
        // A combination the compiler rejects (e.g. a read whose only writer is off) is a
        // user error with a message, not something to render.
        EXPECT_FALSE(e.diagnostics().empty());
        return;
    }
    const RendererOptions ro = genericOptions(2);
    Renderer r(sharedDevice(), std::move(*compiled), ro);
    for (int i = 0; i < 3; ++i) r.renderFrame();
    const bool hasTarget = std::any_of(graph.resources.begin(), graph.resources.end(),
                                       [](const ResourceDesc& d) { return d.final == ExternalState::Present; });
    if (hasTarget) {
        const ImageData img = r.readback();
        EXPECT_EQ(img.width, 16u);
        // Something was really drawn: the Generic default color reaches the target.
        const auto px = img.pixel(8, 8);
        EXPECT_GT(px[0] + px[1] + px[2], 0.0f);
    }
    r.waitIdle();
    EXPECT_EQ(r.lastTimings().size(), r.plan().passes().size()) << "a timing per pass and read-back step";
}

INSTANTIATE_TEST_SUITE_P(Graphs, ShippedGraph, ::testing::ValuesIn(shippedCases()),
                         [](const ::testing::TestParamInfo<GraphCase>& p) { return p.param.label; });

}  // namespace
}  // namespace skygraph::test
