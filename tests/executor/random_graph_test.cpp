// Random Generic graphs (random_graph_generator.hpp): every stage, access, resource type,
// subresource range, feature condition and pass order. Each graph is valid by construction,
// so it must compile, and its plan must run with synchronization validation silent. Seeds
// are fixed so failures reproduce; a failing seed prints its graph and plan. Odd seeds are
// compiled with optimal layouts (settingsForSeed); even seeds also run with their passes on
// random queues (withRandomQueues). 200 seeds here; tools/random-graphs.sh runs 10,000+ with
// the same check.
#include "executor_test_util.hpp"
#include "random_graph_check.hpp"

namespace skygraph::test {
namespace {

constexpr uint32_t kSeedsPerChunk = 25;

/// Seeds [chunk * 25 + 1, chunk * 25 + 25]; one test per chunk so ctest runs chunks in parallel.
class RandomGraphs : public ExecutorTest, public ::testing::WithParamInterface<uint32_t> {};

TEST_P(RandomGraphs, CompileAndRunWithSyncValidationSilent) {
    for (uint32_t seed = GetParam() * kSeedsPerChunk + 1; seed <= (GetParam() + 1) * kSeedsPerChunk; ++seed) {
        const RandomGraph g = generateRandomGraph(seed);
        const GraphRun run = runGraph(sharedDevice(), g.json(), g.features, settingsForSeed(seed));
        EXPECT_TRUE(run.passed()) << "seed " << seed << ":\n" << run.detail << "\n" << g.json();
        // Reordering: the same passes in another order are another valid frame.
        if (seed % 4 == 0) {
            const std::string reordered = g.json(g.shuffledOrder(1));
            const GraphRun again = runGraph(sharedDevice(), reordered, g.features, settingsForSeed(seed));
            EXPECT_TRUE(again.passed()) << "seed " << seed << " reordered:\n" << again.detail << "\n" << reordered;
        }
        // On several queues (one VkQueue here, in submission order, with the plan's semaphores).
        if (seed % 2 == 0) {
            const RandomGraph q = withRandomQueues(g);
            const GraphRun onQueues = runGraph(sharedDevice(), q.json(), q.features, settingsForSeed(seed));
            EXPECT_TRUE(onQueues.passed()) << "seed " << seed << " on queues:\n" << onQueues.detail << "\n" << q.json();
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Seeds, RandomGraphs, ::testing::Range(0u, 8u));

/// The generator really covers the vocabulary it promises: over the CI seeds every
/// resource type, stage, access, binding, range and condition appears.
TEST(RandomGraphGenerator, CoversTheVocabulary) {
    std::string all;
    for (uint32_t seed = 1; seed <= 8 * kSeedsPerChunk; ++seed) all += generateRandomGraph(seed).json();
    for (const char* word :
         {"\"image2d\"", "\"cube\"", "\"image2d_array\"", "\"buffer\"", "ColorAttachment", "DepthAttachment",
          "\"Vertex\"", "\"Fragment\"", "\"Compute\"", "\"Transfer\"", "\"VertexInput\"", "\"Indirect\"",
          "\"Read\"", "\"Write\"", "\"ReadWrite\"", "\"sampled\"", "\"storage\"", "\"uniform\"", "\"index\"",
          "\"mips\": [1,", "\"layers\": [1,", "\"if\": \"", "never_cull", "\"clear\"", "\"external\"",
          "\"final\": \"ShaderRead\"", "\"final\": \"General\"", "\"final\": \"TransferSrc\"", "D24_UNORM_S8_UINT"})
        EXPECT_NE(all.find(word), std::string::npos) << word;
    // External inputs that the frame leaves in another layout, which the final barriers move
    // back to their initial state: read-only ones (one copy) and written ones (one per frame).
    size_t readOnlyReturned = 0, writtenReturned = 0;
    for (uint32_t seed = 1; seed <= 8 * kSeedsPerChunk; ++seed) {
        const RandomGraph g = generateRandomGraph(seed);
        CompileOptions o;
        o.features = g.features;
        o.outputWidth = o.outputHeight = RandomGraphShape{}.outputSize;  // its attachments match there
        const Plan plan = compile(parseGraph(g.json(), "random.json", PassRegistry::withBuiltins()), o);
        for (const Barrier& b : plan.finalBarriers()) {
            if (b.kind != BarrierKind::Image || b.oldLayout == b.newLayout) continue;
            const ResourceCopies copies = plan.resources()[b.resource].copies;
            readOnlyReturned += copies == ResourceCopies::SharedReadOnly;
            writtenReturned += copies == ResourceCopies::PerFrameWrittenNotExported;
        }
    }
    EXPECT_GT(readOnlyReturned, 0u);
    EXPECT_GT(writtenReturned, 5u);
}

/// Small graphs through the brute-force oracle (docs/reliability.md): every barrier dropped
/// or narrowed (a stage bit, an access bit, the layout change) in turn, each weakened plan
/// rendered under synchronization validation. Asserted: dropping an image barrier inside
/// the frame, or only its layout change, is always caught, by the layer or, where the layer
/// is blind (a storage write after a storage write), by the plan verifier. Reported, not
/// asserted: the other weakenings the layer does not notice (cross-frame scopes that the
/// frame fence covers, depth-test stage pairs, and the findings listed in docs/reliability.md).
class BarrierMinimality : public ExecutorTest, public ::testing::WithParamInterface<uint32_t> {};

TEST_P(BarrierMinimality, DroppedImageBarriersAndLayoutChangesAreCaught) {
    allowMessages();  // the mutated plans are meant to produce messages
    RandomGraphShape small;
    small.maxPasses = 3;
    small.maxResources = 2;
    small.maxUsagesPerPass = 2;
    const RandomGraph g = generateRandomGraph(GetParam(), small);
    const GraphRun run = runGraph(sharedDevice(), g.json(), g.features);
    ASSERT_TRUE(run.passed()) << run.detail;
    const MinimalityReport report = checkMinimality(sharedDevice(), *run.compiled);
    ASSERT_GT(report.mutations, 0u);
    ASSERT_TRUE(report.planVerifies) << planToText(run.compiled->plan());
    std::string missed, unnoticed;
    for (const auto& u : report.unneeded) {
        const std::string& d = u.description;
        const bool inFrame = d.rfind("before ", 0) == 0;
        const bool whole = d.find("barrier dropped") != std::string::npos ||
                           d.find("layout change dropped") != std::string::npos;
        // Where the layer is blind (a storage write after a storage write), the plan verifier
        // is the oracle, and it must find the drop.
        const bool caught = u.verifierFinds;
        (inFrame && whole && d.find("(image)") != std::string::npos && !caught ? missed : unnoticed) +=
            "  " + d + (caught ? " (the plan verifier finds it)" : "") + "\n";
    }
    EXPECT_TRUE(missed.empty()) << "image barriers dropped without a message:\n" << missed << planToText(run.compiled->plan())
                                << g.json();
    if (!unnoticed.empty())
        std::printf("seed %u: %zu of %zu weakenings not noticed by the layer:\n%s", GetParam(),
                    report.unneeded.size(), report.mutations, unnoticed.c_str());
}

INSTANTIATE_TEST_SUITE_P(Seeds, BarrierMinimality, ::testing::Range(1u, 6u));

}  // namespace
}  // namespace skygraph::test
