// Every shipped graph under every combination of its features, against a golden plan that was
// reviewed by hand against the Vulkan spec (docs/barriers.md walks through them).
// To regenerate after a deliberate change: SKYGRAPH_UPDATE_GOLDEN=1 ctest -R Golden, then
// review `git diff tests/golden` barrier by barrier before committing.
#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>
#include <skygraph/transfer_plans.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace skygraph {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = SKYGRAPH_SOURCE_DIR;

struct GoldenCase {
    fs::path graph;
    FeatureValues features;
    std::string name;  // e.g. "raster.geometry-on.skybox-off"
};

std::vector<GoldenCase> allCases() {
    std::vector<GoldenCase> cases;
    const PassRegistry registry = PassRegistry::withBuiltins();
    std::vector<fs::path> graphs;
    for (const auto& e : fs::directory_iterator(kSource / "graphs"))
        if (e.path().extension() == ".json") graphs.push_back(e.path());
    std::sort(graphs.begin(), graphs.end());
    for (const auto& path : graphs) {
        const GraphDesc g = loadGraphFile(path, registry);
        const size_t n = g.features.size();
        for (size_t mask = 0; mask < (size_t(1) << n); ++mask) {
            GoldenCase c{path, {}, path.stem().string()};
            for (size_t i = 0; i < n; ++i) {
                const bool on = mask & (size_t(1) << (n - 1 - i));
                c.features[g.features[i].name] = on;
                c.name += "." + g.features[i].name + (on ? "-on" : "-off");
            }
            cases.push_back(std::move(c));
        }
    }
    return cases;
}

std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

/// A small line diff (longest common subsequence) so a failure shows what changed.
std::string diff(const std::string& expected, const std::string& actual) {
    const auto a = lines(expected), b = lines(actual);
    std::vector<std::vector<int>> lcs(a.size() + 1, std::vector<int>(b.size() + 1, 0));
    for (size_t i = a.size(); i-- > 0;)
        for (size_t j = b.size(); j-- > 0;)
            lcs[i][j] = a[i] == b[j] ? lcs[i + 1][j + 1] + 1 : std::max(lcs[i + 1][j], lcs[i][j + 1]);
    std::ostringstream out;
    size_t i = 0, j = 0;
    while (i < a.size() || j < b.size()) {
        if (i < a.size() && j < b.size() && a[i] == b[j]) {
            ++i;
            ++j;
        } else if (j < b.size() && (i == a.size() || lcs[i][j + 1] >= lcs[i + 1][j])) {
            out << "+ " << b[j] << "   (line " << j + 1 << ")\n";
            ++j;
        } else {
            out << "- " << a[i] << "   (line " << i + 1 << ")\n";
            ++i;
        }
    }
    return out.str();
}

void PrintTo(const GoldenCase& c, std::ostream* os) { *os << c.name; }

class Golden : public ::testing::TestWithParam<GoldenCase> {};

/// The frame's plan, with the setup that runs before its first frame under "setup" when there
/// is one.
nlohmann::ordered_json frameAndSetup(const GraphDesc& g, const Plan& frame, const SetupOptions& setup = {}) {
    nlohmann::ordered_json j = planToJson(frame);
    const Plan before = planSetup(g, frame, setup);
    if (!before.passes().empty()) j["setup"] = planToJson(before);
    return j;
}

void expectGolden(const fs::path& golden, const nlohmann::ordered_json& plan) {
    const std::string actual = plan.dump(2) + "\n";
    if (const char* update = std::getenv("SKYGRAPH_UPDATE_GOLDEN"); update && std::string_view(update) == "1")
        std::ofstream(golden, std::ios::binary) << actual;
    ASSERT_TRUE(fs::exists(golden)) << "no golden plan " << golden;
    const std::string expected = readFile(golden);
    EXPECT_EQ(expected, actual) << "plan differs from " << golden << ":\n" << diff(expected, actual);
}

TEST_P(Golden, PlanMatchesReviewedGolden) {
    const GoldenCase& c = GetParam();
    const GraphDesc g = loadGraphFile(c.graph, PassRegistry::withBuiltins());
    CompileOptions options;
    options.features = c.features;
    expectGolden(kSource / "tests" / "golden" / (c.name + ".json"), frameAndSetup(g, compile(g, options)));
}

// How the headless executor runs the shipped graphs: the swapchain target is read back after
// every frame instead of presented, and an environment file is uploaded before the first.
TEST(GoldenTransfers, RasterHeadlessWithAnUploadedEnvironment) {
    const GraphDesc g = loadGraphFile(kSource / "graphs" / "raster.json", PassRegistry::withBuiltins());
    CompileOptions options;
    options.features = {{"environment_file", true}, {"skybox", true}, {"sample_cubemap", false}};
    options.presentReplacement = ExternalState::TransferSrc;
    options.readbacks = {"swapchain"};
    expectGolden(kSource / "tests" / "golden" / "transfers" / "raster.headless.upload-equirect.json",
                 frameAndSetup(g, compile(g, options), SetupOptions{{"equirect"}, {}}));
}

TEST(GoldenTransfers, IblProductsReadBackWithEveryMip) {
    const GraphDesc g = loadGraphFile(kSource / "graphs" / "ibl.json", PassRegistry::withBuiltins());
    const Plan frame = compile(g);
    expectGolden(kSource / "tests" / "golden" / "transfers" / "ibl.read-prefiltered.json",
                 planToJson(planImageRead(g, frame, "prefiltered")));
}

TEST(GoldenTransfers, PathTraceAccumulationReadBackOfAnHdrIntermediate) {
    const GraphDesc g = loadGraphFile(kSource / "graphs" / "pathtrace.json", PassRegistry::withBuiltins());
    CompileOptions options;
    options.presentReplacement = ExternalState::TransferSrc;
    options.readbacks = {"accumulation", "swapchain"};
    expectGolden(kSource / "tests" / "golden" / "transfers" / "pathtrace.headless.read-accumulation.json",
                 frameAndSetup(g, compile(g, options)));
}

TEST_P(Golden, MasksAreNeverWiderThanTheAccesses) {
    const GoldenCase& c = GetParam();
    CompileOptions options;
    options.features = c.features;
    const Plan plan = compile(loadGraphFile(c.graph, PassRegistry::withBuiltins()), options);
    auto check = [](const Barrier& b, bool final = false) {
        // On several queues a barrier that continues a semaphore wait, and every layout
        // transition, carries MEMORY_READ, a no-op for Vulkan that validation layer 1.3.239
        // needs (docs/queues.md). One that continues a wait without a transition holds the
        // wait's stages in its source (the final barriers follow a wait at ALL_COMMANDS, which
        // every stage continues).
        const bool continuesWait = (b.srcAccess & VK_ACCESS_2_MEMORY_READ_BIT) != 0;
        if (continuesWait && !final && b.oldLayout == b.newLayout) {
            EXPECT_EQ(b.srcStages & b.dstStages, b.dstStages);
        }
        const VkAccessFlags2 src = b.srcAccess & ~VK_ACCESS_2_MEMORY_READ_BIT;
        EXPECT_EQ(b.srcStages & VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0u);
        EXPECT_EQ(b.dstStages & VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0u);
        EXPECT_EQ(b.srcStages & VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT, 0u);
        EXPECT_EQ((src | b.dstAccess) & (VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT), 0u);
        EXPECT_EQ(src & ~(VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                          VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT),
                  0u)
            << "a source access mask only ever needs writes";
    };
    const Plan setup = planSetup(loadGraphFile(c.graph, PassRegistry::withBuiltins()), plan);
    for (const Plan* steps : {&plan, &setup}) {
        for (const auto& p : steps->passes())
            for (const auto& b : p.barriers) check(b);
        for (const auto& b : steps->finalBarriers()) check(b, true);
        for (const Submit& submit : steps->submits())
            for (const auto& b : submit.releases) check(b);
    }
}

INSTANTIATE_TEST_SUITE_P(ShippedGraphs, Golden, ::testing::ValuesIn(allCases()),
                         [](const ::testing::TestParamInfo<GoldenCase>& param) {
                             std::string n = param.param.name;
                             for (auto& ch : n)
                                 if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                             return n;
                         });

TEST(GoldenFiles, EveryGoldenBelongsToAShippedCase) {
    std::set<std::string> expected;
    for (const auto& c : allCases()) expected.insert(c.name + ".json");
    for (const auto& e : fs::directory_iterator(kSource / "tests" / "golden"))
        EXPECT_TRUE(e.is_directory() || expected.count(e.path().filename().string()))
            << e.path() << " is stale: no shipped graph and feature combination produces it";
}

}  // namespace
}  // namespace skygraph
