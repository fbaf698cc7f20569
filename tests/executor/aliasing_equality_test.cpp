// Sharing memory changes nothing a frame computes: every shipped graph under every feature
// combination (pairwise in the sanitizer build: shipped_cases.hpp), and random Generic graphs, render byte for byte the same with their transients
// aliased and clobbered (poisoned before the first use that discards them) as with each in
// memory of its own. What is compared is every image the plan exports, the read-back target
// included, with all its mips and layers, after three frames with two in flight (for random
// graphs the read-back, which their chains of transients decide, with one frame in flight, or
// two with the heaps shared between them or one set each). A
// pass that read what it had not written, or a transient bound over another that lives, would
// change the bytes.
#include "executor_test_util.hpp"
#include "fixture_graphs.hpp"
#include "random_graph_generator.hpp"
#include "shipped_cases.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <optional>

namespace skygraph::test {
namespace {

/// How transients live: each in its own memory and untouched, or shared and poisoned.
struct MemoryVariant {
    bool aliasing = false;
    bool clobber = false;
    MemoryStrategy strategy = MemoryStrategy::BestFitBySize;
    bool heapsShared = true;  ///< by the frames in flight, as by default
};

using Images = std::map<std::string, std::vector<ImageData>>;

/// After three frames of `compiled` with `framesInFlight`: every image its plan exports, each
/// mip and layer, or with `readBackOnly` the read-back target alone.
Images renderExports(const CompiledGraph& compiled, uint32_t framesInFlight = 2, bool readBackOnly = false) {
    Renderer r(sharedDevice(), compiled, genericOptions(framesInFlight));
    for (uint32_t i = 0; i < 3; ++i) r.renderFrame();
    Images out;
    for (const PlannedResource& res : r.plan().resources()) {
        const ResourceDesc& d = r.graph().resources[res.decl];
        if (!d.isImage() || !d.isExported()) continue;
        if (readBackOnly && !compiled.options().readbacks.count(d.name)) continue;
        try {
            out[d.name] = r.readImage(d.name);
        } catch (const ExecutorError& e) {
            // Formats readImage does not convert (packed, integer, stencil) are left out.
            if (std::string(e.what()).find("not supported for read-back") == std::string::npos) throw;
        }
    }
    r.waitIdle();
    return out;
}

/// `graph` headless with `o` (features, size) and `v`'s memory, on the shared device.
CompiledGraph compileWith(const GraphDesc& graph, CompileOptions o, const MemoryVariant& v) {
    o.memory = sharedDevice().memoryModel();
    o.aliasing = v.aliasing;
    o.clobberTransients = v.clobber;
    o.placement = v.strategy;
    o.shareTransientsAcrossFrames = v.heapsShared;
    o = headless(graph, std::move(o));
    return CompiledGraph(graph, std::move(o));
}

/// Empty when `a` and `b` hold the same bytes; else where they first differ.
std::string difference(const Images& a, const Images& b) {
    if (a.empty()) return "no image was compared";
    if (a.size() != b.size()) return "different images were exported";
    for (const auto& [name, levels] : a) {
        const std::vector<ImageData>& other = b.at(name);
        if (levels.size() != other.size()) return name + ": different mip or layer counts";
        for (size_t l = 0; l < levels.size(); ++l) {
            const std::vector<float>& x = levels[l].rgba;
            const std::vector<float>& y = other[l].rgba;
            if (x.size() != y.size()) return name + ": different sizes";
            for (size_t i = 0; i < x.size(); ++i)
                if (std::memcmp(&x[i], &y[i], sizeof(float)) != 0)
                    return name + " level*layer " + std::to_string(l) + ", texel " + std::to_string(i / 4) +
                           " channel " + std::to_string(i % 4) + ": " + std::to_string(x[i]) + " unaliased, " +
                           std::to_string(y[i]) + " aliased and clobbered";
        }
    }
    return {};
}

/// The deferred frame's mip chains (output/2 with 6 levels) need 64x64; the rest is as small.
constexpr uint32_t kSize = 64;

class AliasedShippedGraph : public ExecutorTest, public ::testing::WithParamInterface<GraphCase> {};

TEST_P(AliasedShippedGraph, RendersTheSameBytesAsUnaliased) {
    const GraphCase& gc = GetParam();
    const GraphDesc graph = loadGraphFile(gc.file, PassRegistry::withBuiltins());
    CompileOptions o = sizedOptions(kSize, kSize);
    o.features = gc.features;
    try {
        (void)compile(graph, headless(graph, o));
    } catch (const GraphError& e) {
        EXPECT_FALSE(e.diagnostics().empty());  // a combination the compiler rejects, as ShippedGraph
        return;
    }
    // A combination that compiles by default compiles unaliased and aliased and clobbered too.
    const CompiledGraph unaliased = compileWith(graph, o, {});
    const CompiledGraph aliased = compileWith(graph, o, {true, true});
    const std::string why = difference(renderExports(unaliased), renderExports(aliased));
    EXPECT_TRUE(why.empty()) << why;
}

INSTANTIATE_TEST_SUITE_P(Graphs, AliasedShippedGraph, ::testing::ValuesIn(shippedCases()),
                         [](const ::testing::TestParamInfo<GraphCase>& p) { return p.param.label; });

using AliasedFixture = ExecutorTest;

// A resource taking over memory whose first pass writes one layer as a colour attachment and
// the other in a dispatch: both in GENERAL after one aliasing barrier. The layer cannot see
// hazards between aliased images (the verifier's regression test is the oracle for that
// barrier); this runs the layouts it leads to, a colour attachment in GENERAL beside storage
// writes of the same image, under validation. (Not clobbered: the Clobber step would be b's
// first, in one layout.)
TEST_F(AliasedFixture, AFirstPassInSeveralLayoutsRendersTheSameBytesAsUnaliased) {
    const GraphDesc graph = parseGraph(fixtures::kMixedLayoutsTakingOverMemory, "mixed_layouts_aliased.json",
                                       PassRegistry::withBuiltins());
    const CompileOptions o = sizedOptions();
    // Heaps per frame: b alone in them keeps its usages' own layouts.
    const CompiledGraph unaliased = compileWith(graph, o, {false, false, MemoryStrategy::BestFitBySize, false});
    const CompiledGraph aliased = compileWith(graph, o, {true, false});
    const Plan& plan = aliased.plan();
    const PlannedResource& b = plan.resources()[plan.resourceIndex("b")];
    ASSERT_NE(b.placement, PlannedResource::kNoPlacement);
    ASSERT_FALSE(plan.memory().placements[b.placement].aliases.empty()) << "b takes over a's memory";
    for (const PlannedPass& p : plan.passes()) {
        if (p.name != "write_b") continue;
        for (const PlannedUsage& u : p.usages) EXPECT_EQ(u.layout, VK_IMAGE_LAYOUT_GENERAL) << planToText(plan);
    }
    for (const PlannedPass& p : unaliased.plan().passes()) {
        if (p.name != "write_b") continue;
        EXPECT_EQ(p.usages[0].layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL) << planToText(unaliased.plan());
    }
    const std::string why = difference(renderExports(unaliased), renderExports(aliased));
    EXPECT_TRUE(why.empty()) << why << "\n" << planToText(plan);
}

/// A seed of the random-graph generator with two chains of short-lived transients without
/// `clear` (RandomGraphShape::chains), which the read-back depends on: every graph shares
/// memory and clobbers. Placed best-fit by size (odd seeds) or in order of first use (even
/// ones).
struct RandomCase {
    uint32_t seed = 0;
    /// One, as the random-graph suite (frame copies change no barrier); two for the seeds
    /// whose frames can race each other without rule 16 and the persistent final barrier (an
    /// alias that must wait for every earlier holder of its bytes).
    uint32_t framesInFlight = 1;
    /// Frames in flight share the transients' heaps (the default) or each has its own.
    bool heapsShared = true;
};

// Names the case in test listings (gtest would print the struct's bytes, padding included).
void PrintTo(const RandomCase& c, std::ostream* out) {
    *out << "seed " << c.seed << ", " << c.framesInFlight << " frame(s) in flight, heaps "
         << (c.heapsShared ? "shared" : "per frame");
}

class AliasedRandomGraph : public ExecutorTest, public ::testing::WithParamInterface<RandomCase> {};

TEST_P(AliasedRandomGraph, RendersTheSameBytesAsUnaliased) {
    const uint32_t seed = GetParam().seed;
    RandomGraphShape shape;
    shape.chains = 2;
    const RandomGraph g = generateRandomGraph(seed, shape);
    const GraphDesc graph = parseGraph(g.json(), "<random>", PassRegistry::withBuiltins());
    CompileOptions o = sizedOptions();
    o.features = g.features;
    const CompiledGraph unaliased = compileWith(graph, o, {});
    const CompiledGraph aliased =
        compileWith(graph, o,
                    {true, true, seed % 2 ? MemoryStrategy::BestFitBySize : MemoryStrategy::FirstUseOrder,
                     GetParam().heapsShared});
    const Plan& plan = aliased.plan();
    EXPECT_TRUE(std::any_of(plan.memory().placements.begin(), plan.memory().placements.end(),
                            [](const MemoryPlacement& p) { return !p.aliases.empty(); }))
        << "it shares no memory";
    EXPECT_TRUE(std::any_of(plan.passes().begin(), plan.passes().end(),
                            [](const PlannedPass& p) { return p.type == "Clobber"; }))
        << "it clobbers nothing";
    const uint32_t frames = GetParam().framesInFlight;
    const std::string why =
        difference(renderExports(unaliased, frames, true), renderExports(aliased, frames, true));
    EXPECT_TRUE(why.empty()) << why << "\n" << planToText(plan) << "\n" << g.json();
    EXPECT_EQ(sharedDevice().messageCount(), 0u)
        << formatMessages(sharedDevice()) << planToText(plan) << "\n" << g.json();
    sharedDevice().clearMessages();  // reported here, with the plan
}

std::vector<RandomCase> randomCases() {
    std::vector<RandomCase> cases;
    for (uint32_t seed = 1; seed <= 32; ++seed) cases.push_back({seed, 1});
    for (const uint32_t seed : {12u, 36u, 47u, 50u, 60u, 72u, 94u, 105u, 107u, 112u, 115u}) {
        cases.push_back({seed, 2, true});
        cases.push_back({seed, 2, false});
    }
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Seeds, AliasedRandomGraph, ::testing::ValuesIn(randomCases()),
                         [](const ::testing::TestParamInfo<RandomCase>& p) {
                             return "seed" + std::to_string(p.param.seed) + "_" +
                                    std::to_string(p.param.framesInFlight) + "InFlight" +
                                    (p.param.heapsShared ? "" : "_HeapsPerFrame");
                         });

}  // namespace
}  // namespace skygraph::test
