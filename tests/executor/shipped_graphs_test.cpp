// Every shipped graph (graphs/*.json), under every feature combination (a pairwise covering
// set of them in the sanitizer build: shipped_cases.hpp), runs 3 frames with 2
// in flight on the validated device with zero messages; so do those whose plans change under
// LayoutPolicy::Optimal (each reader of an image in its optimal layout) compiled that way.
// Every pass runs as Generic (genericPasses()): it performs exactly the accesses it declares.
#include "executor_test_util.hpp"
#include "shipped_cases.hpp"

#include <algorithm>
#include <optional>

namespace skygraph::test {
namespace {

/// Where the cases render: the smallest output at which graphs/deferred.json's mip chains
/// (bloom's six levels at half the output) fit, which 16x16 is not.
constexpr VkExtent2D kSize{64, 48};

/// Renders `gc` headless at kSize for three frames, with the graph's layouts policy unless
/// `layouts`.
void runThreeFrames(const GraphCase& gc, std::optional<LayoutPolicy> layouts) {
    const VkExtent2D size = kSize;
    const auto registry = PassRegistry::withBuiltins();
    const GraphDesc graph = loadGraphFile(gc.file, registry);
    CompileOptions o = sizedOptions(size.width, size.height);
    o.features = gc.features;
    o.layouts = layouts;
    std::optional<CompiledGraph> compiled;
    try {
        compiled.emplace(graph, headless(graph, o));
    } catch (const GraphError& e) {
        FAIL() << "every shipped combination compiles at " << size.width << "x" << size.height << ":\n"
               << e.diagnostics().format();
    }
    const RendererOptions ro = genericOptions(2);
    Renderer r(sharedDevice(), std::move(*compiled), ro);
    for (int i = 0; i < 3; ++i) r.renderFrame();
    const bool hasTarget = std::any_of(graph.resources.begin(), graph.resources.end(),
                                       [](const ResourceDesc& d) { return d.final == ExternalState::Present; });
    if (hasTarget) {
        const ImageData img = r.readback();
        EXPECT_EQ(img.width, size.width);
        // Something was really drawn: the Generic default color reaches the target.
        const auto px = img.pixel(8, 8);
        EXPECT_GT(px[0] + px[1] + px[2], 0.0f);
    }
    r.waitIdle();
    EXPECT_EQ(r.lastTimings().size(), r.plan().passes().size()) << "a timing per pass and read-back step";
}

class ShippedGraph : public ExecutorTest, public ::testing::WithParamInterface<GraphCase> {};

TEST_P(ShippedGraph, RunsThreeFramesCleanly) { runThreeFrames(GetParam(), std::nullopt); }

INSTANTIATE_TEST_SUITE_P(Graphs, ShippedGraph, ::testing::ValuesIn(shippedCases()),
                         [](const ::testing::TestParamInfo<GraphCase>& p) { return p.param.label; });

/// The shipped cases whose headless plan LayoutPolicy::Optimal changes (the rest would run the
/// plan the suite above runs). A case that does not compile fails the suite above.
std::vector<GraphCase> casesOptimalLayoutsChange() {
    std::vector<GraphCase> changed;
    const auto registry = PassRegistry::withBuiltins();
    for (const GraphCase& gc : shippedCases()) {
        const GraphDesc graph = loadGraphFile(gc.file, registry);
        CompileOptions o = sizedOptions(kSize.width, kSize.height);
        o.features = gc.features;
        o = headless(graph, o);
        o.layouts = LayoutPolicy::FewestBarriers;
        nlohmann::ordered_json fewest;
        try {
            fewest = planToJson(compile(graph, o));
        } catch (const GraphError&) {
            continue;  // a combination the compiler rejects: ShippedGraph checks how
        }
        o.layouts = LayoutPolicy::Optimal;
        try {
            auto optimal = planToJson(compile(graph, o));
            optimal.erase("layouts");
            if (optimal != fewest) changed.push_back(gc);
        } catch (const GraphError&) {
            changed.push_back(gc);  // compiles with fewest barriers only: the case runs, and fails
        }
    }
    return changed;
}

class ShippedGraphOptimalLayouts : public ExecutorTest, public ::testing::WithParamInterface<GraphCase> {};

TEST_P(ShippedGraphOptimalLayouts, RunsThreeFramesCleanly) {
    runThreeFrames(GetParam(), LayoutPolicy::Optimal);
}

INSTANTIATE_TEST_SUITE_P(Graphs, ShippedGraphOptimalLayouts, ::testing::ValuesIn(casesOptimalLayoutsChange()),
                         [](const ::testing::TestParamInfo<GraphCase>& p) { return p.param.label; });

/// A graph file asking for optimal layouts, whose image is read by a copy, a compute sampler,
/// a compute storage load, a fragment sampler and a copy again with no write between: four
/// transitions between reads, each checked by synchronization validation.
TEST_F(ExecutorTest, OptimalLayoutsTransitionBetweenReadsCleanly) {
    std::string json = graphWithSwapchain("optimal_reads", R"(
        "img":  { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" },
        "copy": { "type": "buffer", "size": 4096 })", R"(
        { "name": "produce", "type": "Generic", "uses": { "img": "Write@Compute" } },
        { "name": "copy_out", "type": "Generic", "never_cull": true, "uses": { "img": "Read@Transfer", "copy": "Write@Transfer" } },
        { "name": "sample", "type": "Generic", "never_cull": true, "uses": { "img": "Read@Compute" } },
        { "name": "load", "type": "Generic", "never_cull": true,
          "uses": [ { "resource": "img", "access": "Read", "stage": "Compute", "as": "storage" } ] },
        { "name": "draw", "type": "Generic", "uses": { "img": "Read@Fragment", "swapchain": "Write@ColorAttachment" } },
        { "name": "copy_again", "type": "Generic", "never_cull": true, "uses": { "img": "Read@Transfer", "copy": "ReadWrite@Transfer" } })");
    json.insert(json.find(R"("resources")"), R"("layouts": "optimal", )");
    const CompiledGraph c = compileText(json);
    ASSERT_EQ(c.plan().layouts(), LayoutPolicy::Optimal);
    size_t transitionsBetweenReads = 0;
    for (const PlannedPass& p : c.plan().passes())
        for (const Barrier& b : p.barriers)
            transitionsBetweenReads += b.srcAccess == 0 && b.oldLayout != b.newLayout &&
                                       b.oldLayout != VK_IMAGE_LAYOUT_UNDEFINED && c.plan().resources()[b.resource].name == "img";
    EXPECT_EQ(transitionsBetweenReads, 4u) << planToText(c.plan());
    const ImageData img = render(c);
    const auto px = img.pixel(8, 8);
    EXPECT_GT(px[0] + px[1] + px[2], 0.0f);
}

TEST(ShippedGraphOptimalLayoutsCases, SomeShippedPlanChanges) {
    // graphs/deferred.json copies its TAA result before sampling it: a run of reads that
    // FewestBarriers keeps in GENERAL.
    EXPECT_FALSE(casesOptimalLayoutsChange().empty());
}

}  // namespace
}  // namespace skygraph::test
