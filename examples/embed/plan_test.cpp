// The example's own graph under skygraph::testing, as an engine's CI would test it: the plan
// against its reviewed golden (golden/), the barrier a reviewer cares about, the plan verifier,
// the path an error names, and three frames under validation.
#include "vignette_pass.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/golden.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/testing/assertions.hpp>
#include <skygraph/testing/barrier_matchers.hpp>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace skygraph;
using namespace skygraph::testkit;

struct VignetteGraph {
    PassLibrary library = [] {
        PassLibrary l = PassLibrary::withBuiltins();
        l.add(embed::vignettePassType(), embed::makeVignettePass);
        return l;
    }();
    GraphDesc graph = loadGraphFile(EMBED_DATA_DIR "/vignette.json", library.registry());
};

TEST(VignettePlan, MatchesItsReviewedGolden) {
    const VignetteGraph v;
    const Plan plan = compile(v.graph);
    EXPECT_TRUE(matchesGolden(plan, EMBED_DATA_DIR "/golden/" + goldenFileName(v.graph, plan.features())));
}

TEST(VignettePlan, TheVignetteSamplesWhatTheClearWrote) {
    const VignetteGraph v;
    const Plan plan = compile(v.graph);
    EXPECT_THAT(barriersBefore(plan, "vignette"),
                ::testing::Contains(barrier("hdr_color").readAfterWrite().from(Stage::Transfer).to(Stage::Fragment).into(
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)));
    // The clear takes over hdr_color's bytes from the previous frame, which the vignette
    // sampled and the clear wrote: one barrier orders both.
    EXPECT_THAT(barriersBefore(plan, "clear hdr_color"),
                ::testing::Contains(barrier("hdr_color").writeAfterRead().from(Stage::Fragment).to(Stage::Transfer).into(
                    VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL)));
    EXPECT_TRUE(verifies(plan, v.graph));
}

// A key the vignette does not know, holding a dot: the message's path says which key it is.
TEST(VignettePlan, AnUnknownParamsKeyIsNamedByItsPath) {
    const VignetteGraph v;
    const std::string text = R"({ "version": 1, "resources": {
        "in": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output" },
        "out": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output" } },
      "passes": [ { "name": "vignette", "type": "VignettePass",
        "uses": { "in": "Read@Fragment", "out": "Write@ColorAttachment" },
        "params": { "strength.max": 1 } } ] })";
    try {
        (void)parseGraph(text, "dotted.json", v.library.registry());
        ADD_FAILURE() << "an unknown params key was accepted";
    } catch (const GraphError& e) {
        EXPECT_THAT(e.what(), ::testing::HasSubstr(R"(dotted.json: passes[0].params["strength.max"]: pass 'vignette')"));
        EXPECT_THAT(e.what(), ::testing::HasSubstr("unknown parameter; expected strength"));
    }
}

TEST(VignettePlan, RendersWithoutValidationMessages) {
    const VignetteGraph v;
    DeviceOptions options;
    options.validation = true;
    const auto device = Device::create(options);
    CompileOptions co;
    co.outputWidth = co.outputHeight = 64;
    co.presentReplacement = ExternalState::TransferSrc;  // headless
    RendererOptions ro;
    ro.passes = &v.library;
    ro.shaderDir = SKYGRAPH_PACKAGE_SHADER_DIR;
    EXPECT_TRUE(rendersWithoutValidationMessages(*device, CompiledGraph(v.graph, co), ro));
}

}  // namespace
