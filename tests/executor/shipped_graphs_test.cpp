// Every shipped graph (graphs/*.json), under every feature combination, runs 3 frames with 2
// in flight on the validated device with zero messages. Every pass runs as Generic
// (genericPasses()): it performs exactly the accesses it declares.
#include "executor_test_util.hpp"

#include <algorithm>
#include <filesystem>
#include <optional>

namespace skygraph::test {
namespace {

struct GraphCase {
    std::string file;
    FeatureValues features;
    std::string label;
};

std::vector<GraphCase> shippedCases() {
    std::vector<GraphCase> cases;
    const std::filesystem::path dir = std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs";
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
        if (e.path().extension() == ".json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    const auto registry = PassRegistry::withBuiltins();
    for (const auto& f : files) {
        GraphDesc g;
        try {
            g = loadGraphFile(f, registry);
        } catch (const std::exception&) {
            cases.push_back({f.string(), {}, f.stem().string() + "_unloadable"});
            continue;
        }
        const size_t n = g.features.size();
        for (uint64_t mask = 0; mask < (uint64_t(1) << n); ++mask) {
            GraphCase c{f.string(), {}, f.stem().string()};
            for (size_t i = 0; i < n; ++i) {
                const bool on = (mask >> i) & 1u;
                c.features[g.features[i].name] = on;
                c.label += "_" + g.features[i].name + (on ? "On" : "Off");
            }
            std::replace_if(c.label.begin(), c.label.end(),
                            [](char ch) { return !std::isalnum(static_cast<unsigned char>(ch)) && ch != '_'; },
                            '_');
            cases.push_back(std::move(c));
        }
    }
    return cases;
}

void PrintTo(const GraphCase& c, std::ostream* os) { *os << c.label; }

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
