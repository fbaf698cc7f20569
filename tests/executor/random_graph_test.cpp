// Random Generic graphs: whatever order of accesses a user writes, the compiler's barriers
// must keep synchronization validation silent. Seeds are fixed so failures reproduce; each
// failing seed prints its graph.
#include "executor_test_util.hpp"

#include <random>
#include <sstream>

namespace skygraph::test {
namespace {

struct ResourceKind {
    const char* name;
    const char* decl;
    std::vector<const char*> usages;  ///< Access@Stage[@as]
};

const std::vector<ResourceKind>& kinds() {
    static const std::vector<ResourceKind> k = {
        {"color", R"({ "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "clear": { "color": [0.1, 0.2, 0.3, 1] } })",
         {"Write@ColorAttachment", "ReadWrite@ColorAttachment", "Read@Fragment", "Read@Compute",
          "Write@Compute", "ReadWrite@Compute", "Read@Transfer", "Write@Transfer", "Read@Vertex",
          "Read@Fragment@storage"}},
        {"hdr", R"({ "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output/2", "clear": { "color": [0, 0, 0, 1] } })",
         {"Write@ColorAttachment", "ReadWrite@ColorAttachment", "Read@Fragment", "Write@Compute",
          "ReadWrite@Fragment", "Write@Transfer", "Read@Transfer"}},
        {"depth", R"({ "type": "image2d", "format": "D32_SFLOAT", "extent": "output", "clear": { "depth": 1.0 } })",
         {"Write@DepthAttachment", "Read@DepthAttachment", "ReadWrite@DepthAttachment", "Read@Fragment",
          "Read@Compute"}},
        {"buf", R"({ "type": "buffer", "size": 256, "external": true, "final": "General" })",
         {"Write@Compute", "Read@Compute", "ReadWrite@Compute", "Read@Fragment", "Read@VertexInput",
          "Read@Indirect", "Write@Transfer", "Read@Transfer", "Read@Vertex@uniform", "Write@Fragment"}},
    };
    return k;
}

std::string usageJson(const std::string& resource, const std::string& spec) {
    std::vector<std::string> parts;
    std::stringstream ss(spec);
    for (std::string p; std::getline(ss, p, '@');) parts.push_back(p);
    std::string s = R"({ "resource": ")" + resource + R"(", "access": ")" + parts[0] +
                    R"(", "stage": ")" + parts[1] + "\"";
    if (parts.size() > 2) s += R"(, "as": ")" + parts[2] + "\"";
    return s + " }";
}

std::string randomGraph(uint32_t seed) {
    std::mt19937 rng(seed);
    auto pick = [&](size_t n) { return static_cast<size_t>(rng() % n); };
    // Two instances of each kind.
    std::vector<std::pair<std::string, size_t>> resources;
    std::string decls;
    for (size_t k = 0; k < kinds().size(); ++k)
        for (int i = 0; i < 2; ++i) {
            const std::string name = std::string(kinds()[k].name) + std::to_string(i);
            resources.emplace_back(name, k);
            decls += "\"" + name + "\": " + kinds()[k].decl + ",\n";
        }
    decls += R"("swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                 "external": true, "final": "Present" })";
    std::string passes;
    const size_t passCount = 3 + pick(6);
    for (size_t p = 0; p < passCount; ++p) {
        std::vector<size_t> used;
        bool depth = false;
        std::string uses;
        const size_t n = 1 + pick(3);
        for (size_t u = 0; u < n; ++u) {
            const size_t r = pick(resources.size());
            if (std::find(used.begin(), used.end(), r) != used.end()) continue;
            const auto& kind = kinds()[resources[r].second];
            std::string spec = kind.usages[pick(kind.usages.size())];
            if (spec.find("DepthAttachment") != std::string::npos) {
                if (depth) continue;
                depth = true;
            }
            used.push_back(r);
            uses += (uses.empty() ? "" : ", ") + usageJson(resources[r].first, spec);
        }
        passes += R"({ "name": "p)" + std::to_string(p) + R"(", "type": "Generic", "never_cull": true, "uses": [ )" +
                  uses + " ] },\n";
    }
    passes += R"({ "name": "present", "type": "Generic", "uses": [ { "resource": "color0", "access": "Read", "stage": "Fragment" },
                  { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] })";
    return R"({ "version": 1, "name": "random", "resources": {)" + decls + R"(}, "passes": [)" + passes + "] }";
}

class RandomGraph : public ExecutorTest, public ::testing::WithParamInterface<uint32_t> {};

TEST_P(RandomGraph, SyncValidationStaysSilent) {
    const std::string text = randomGraph(GetParam());
    Compiled c;
    try {
        c = compileText(text);
    } catch (const GraphError& e) {
        // A combination the compiler rejects (e.g. attachments of different sizes in one
        // pass) must come with a message; nothing to render.
        EXPECT_FALSE(e.diagnostics().empty());
        return;
    }
    SCOPED_TRACE(text);
    RendererOptions o;
    o.width = 16;
    o.height = 16;
    o.framesInFlight = 2;
    Renderer r(sharedDevice(), c.graph, c.plan, o);
    for (int i = 0; i < 3; ++i) r.renderFrame();
    (void)r.readback();
    r.waitIdle();
    if (sharedDevice().messageCount() != 0) ADD_FAILURE() << planToText(c.plan);
}

INSTANTIATE_TEST_SUITE_P(Seeds, RandomGraph, ::testing::Range(1u, 41u));

}  // namespace
}  // namespace skygraph::test
