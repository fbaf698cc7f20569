// skygraph::testing on real plans and lavapipe: each assertion and matcher passes where it
// should and, on a plan with one barrier dropped or a golden edited, fails with a message that
// says what is wrong.
#include <skygraph/compiled_graph.hpp>
#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/golden.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/testing/assertions.hpp>
#include <skygraph/testing/barrier_matchers.hpp>

#include "compiled_graph_access.hpp"
#include "plan_editor.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace skygraph {
namespace {

namespace fs = std::filesystem;
using ::testing::Contains;
using ::testing::Not;
using namespace skygraph::testing;

const fs::path kSource = SKYGRAPH_SOURCE_DIR;

struct Raster {
    GraphDesc graph = loadGraphFile(kSource / "graphs" / "raster.json", PassRegistry::withBuiltins());
    Plan plan = compile(graph);
};

std::string explain(const ::testing::Matcher<const NamedBarrier&>& m, const NamedBarrier& b) {
    ::testing::StringMatchResultListener listener;
    EXPECT_FALSE(m.MatchAndExplain(b, &listener));
    return listener.str();
}

TEST(BarrierMatchers, TheTonemapBarrierIsAReadAfterWriteIntoShaderReadOnly) {
    const Raster r;
    const auto before = barriersBefore(r.plan, "tonemap");
    EXPECT_THAT(before, Contains(barrier("hdr_color")
                                     .readAfterWrite()
                                     .from(Stage::ColorAttachment)
                                     .to(Stage::Fragment)
                                     .fromLayout(VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL)
                                     .into(VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)));
    EXPECT_THAT(before, Contains(barrier("swapchain").writeAfterRead().into(VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL)));
    EXPECT_THAT(finalBarriers(r.plan), Contains(barrier("swapchain").into(VK_IMAGE_LAYOUT_PRESENT_SRC_KHR)));
    EXPECT_THAT(before, Not(Contains(barrier("hdr_color").to(Stage::Compute))));
}

TEST(BarrierMatchers, MismatchesSayWhichPartDiffers) {
    const Raster r;
    const auto before = barriersBefore(r.plan, "tonemap");
    const NamedBarrier* hdr = nullptr;
    for (const NamedBarrier& b : before)
        if (b.resource == "hdr_color") hdr = &b;
    ASSERT_NE(hdr, nullptr);
    EXPECT_EQ(explain(barrier("depth"), *hdr), "it is on hdr_color");
    EXPECT_THAT(explain(barrier("hdr_color").writeAfterRead(), *hdr),
                ::testing::StartsWith("it is not a write-after-read: VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT"));
    EXPECT_THAT(explain(barrier("hdr_color").to(Stage::Compute), *hdr), ::testing::StartsWith("it does not block Compute"));
    EXPECT_EQ(explain(barrier("hdr_color").into(VK_IMAGE_LAYOUT_GENERAL), *hdr),
              "it leaves the image in VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL");
    EXPECT_EQ(::testing::DescribeMatcher<const NamedBarrier&>(
                  barrier("hdr_color").readAfterWrite().from(Stage::ColorAttachment).to(Stage::Fragment)),
              "is a barrier on hdr_color, a read-after-write, from ColorAttachment, to Fragment");
    try {
        (void)barriersBefore(r.plan, "nosuch");
        FAIL();
    } catch (const std::out_of_range& e) {
        EXPECT_NE(std::string(e.what()).find("no step 'nosuch'; its steps are: forward, skybox, tonemap"),
                  std::string::npos) << e.what();
    }
}

class GoldenAssertion : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("skygraph_kit_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

TEST_F(GoldenAssertion, WritesWhenAskedThenMatchesThenShowsTheDiff) {
    const Raster r;
    const fs::path golden = dir_ / goldenFileName(r.graph, r.plan.features());
    const ::testing::AssertionResult missing = matchesGolden(r.plan, golden);
    EXPECT_FALSE(missing);
    EXPECT_THAT(missing.message(), ::testing::HasSubstr("golden missing: no golden plan " + golden.string()));
    ::setenv("SKYGRAPH_UPDATE_GOLDEN", "1", 1);
    const ::testing::AssertionResult written = matchesGolden(r.plan, golden);
    ::unsetenv("SKYGRAPH_UPDATE_GOLDEN");
    EXPECT_TRUE(written);
    EXPECT_TRUE(matchesGolden(r.plan, golden));
    CompileOptions noSkybox;
    noSkybox.features = {{"skybox", false}};
    const ::testing::AssertionResult differs = matchesGolden(compile(r.graph, noSkybox), golden);
    EXPECT_FALSE(differs);
    EXPECT_THAT(differs.message(), ::testing::HasSubstr("+++ compiled"));
    EXPECT_THAT(differs.message(), ::testing::HasSubstr("-[1] skybox (SkyboxPass)"));
}

TEST(VerifierAssertion, PassesThePlanAndNamesWhatAWeakenedBarrierBreaks) {
    const Raster r;
    EXPECT_TRUE(verifies(r.plan, r.graph));
    Plan broken = r.plan;
    const size_t tonemap = 2;
    ASSERT_EQ(broken.passes()[tonemap].name, "tonemap");
    for (Barrier& b : detail::PlanEditor::barriersOf(broken, tonemap))
        if (broken.resources()[b.resource].name == "hdr_color") b.dstStages = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    const ::testing::AssertionResult result = verifies(broken, r.graph);
    EXPECT_FALSE(result);
    EXPECT_THAT(result.message(), ::testing::HasSubstr("the plan verifier found"));
    EXPECT_THAT(result.message(), ::testing::HasSubstr("hdr_color"));
}

TEST(ValidationRunAssertion, CleanFramesPassAndADroppedBarrierIsReported) {
    DeviceOptions options;
    options.validation = true;
    options.logMessages = false;
    const auto device = Device::create(options);
    const PassLibrary library = PassLibrary::withBuiltins();
    RendererOptions ro;
    ro.passes = &library;
    const GraphDesc graph = loadGraphFile(kSource / "graphs" / "pathtrace.json", library.registry());
    CompileOptions co;
    co.outputWidth = co.outputHeight = 32;
    co.presentReplacement = ExternalState::TransferSrc;
    co.memory = device->memoryModel();  // else the renderer recompiles, and the edit below is lost
    const CompiledGraph compiled(graph, co);
    EXPECT_TRUE(rendersWithoutValidationMessages(*device, compiled, ro, 2));

    Plan broken = compiled.plan();
    bool dropped = false;
    for (size_t p = 0; p < broken.passes().size() && !dropped; ++p)
        if (broken.passes()[p].name == "tonemap" && !broken.passes()[p].barriers.empty()) {
            detail::PlanEditor::eraseBarrier(broken, p, 0);
            dropped = true;
        }
    ASSERT_TRUE(dropped);
    const ::testing::AssertionResult result =
        rendersWithoutValidationMessages(*device, detail::CompiledGraphAccess::withPlan(compiled, broken), ro, 2);
    EXPECT_FALSE(result);
    EXPECT_THAT(result.message(), ::testing::HasSubstr("validation message(s) in 2 frame(s)"));
    EXPECT_THAT(result.message(), ::testing::HasSubstr("SYNC-HAZARD"));
    device->clearMessages();

    const auto silent = Device::create({});
    EXPECT_THAT(rendersWithoutValidationMessages(*silent, compiled, ro).message(),
                ::testing::HasSubstr("created without validation"));
}

}  // namespace
}  // namespace skygraph
