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
#include <optional>
#include <string>
#include <unistd.h>

namespace skygraph {
namespace {

namespace fs = std::filesystem;
using ::testing::Contains;
using ::testing::Not;
using namespace skygraph::testkit;

const fs::path kSource = SKYGRAPH_SOURCE_DIR;

struct Raster {
    GraphDesc graph = loadGraphFile(kSource / "graphs" / "raster.json", PassRegistry::withBuiltins());
    Plan plan = compile(graph);
};

bool matches(const ::testing::Matcher<const NamedBarrier&>& m, const NamedBarrier& b) { return m.Matches(b); }

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

TEST(BarrierMatchers, StagesMustBeCoveredWholeAndWriteAfterReadIgnoresTheSourceAccess) {
    NamedBarrier b{"depth", {}};
    b.barrier.srcStages = VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT;  // half of a depth test
    b.barrier.dstStages = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    b.barrier.srcAccess = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    b.barrier.dstAccess = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
    const ::testing::Matcher<const NamedBarrier&> fromDepth = barrier("depth").from(Stage::DepthAttachment);
    EXPECT_THAT(explain(fromDepth, b), ::testing::StartsWith("it does not wait for DepthAttachment"));
    b.barrier.srcStages |= VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    EXPECT_TRUE(fromDepth.Matches(b));
    b.barrier.srcStages = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;  // umbrella stages count as what they hold
    EXPECT_TRUE(fromDepth.Matches(b));
    b.barrier.srcStages = VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT;
    EXPECT_TRUE(fromDepth.Matches(b));
    EXPECT_FALSE(matches(barrier("depth").from(Stage::Compute), b));

    // After a sampled read and a write, a clear's transition resolves both.
    NamedBarrier clear{"hdr", {}};
    clear.barrier.srcStages = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT;
    clear.barrier.srcAccess = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    clear.barrier.dstStages = VK_PIPELINE_STAGE_2_TRANSFER_BIT;
    clear.barrier.dstAccess = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    clear.barrier.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    EXPECT_TRUE(matches(barrier("hdr").writeAfterRead().from(Stage::Fragment).to(Stage::Transfer), clear));
    EXPECT_TRUE(matches(barrier("hdr").writeAfterWrite().from(Stage::Transfer), clear));
    EXPECT_FALSE(matches(barrier("hdr").readAfterWrite(), clear));
}

TEST(BarrierMatchers, MismatchesSayWhichPartDiffers) {
    const Raster r;
    const auto before = barriersBefore(r.plan, "tonemap");
    const NamedBarrier* hdr = nullptr;
    for (const NamedBarrier& b : before)
        if (b.resource == "hdr_color") hdr = &b;
    ASSERT_NE(hdr, nullptr);
    EXPECT_EQ(explain(barrier("depth"), *hdr), "it is on hdr_color");
    const NamedBarrier* swapchain = nullptr;
    for (const NamedBarrier& b : before)
        if (b.resource == "swapchain") swapchain = &b;
    ASSERT_NE(swapchain, nullptr);
    EXPECT_EQ(explain(barrier("swapchain").readAfterWrite(), *swapchain),
              "it is not a read-after-write: VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT / NONE -> "
              "VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT / VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, "
              "VK_IMAGE_LAYOUT_UNDEFINED -> VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL");
    EXPECT_THAT(explain(barrier("hdr_color").from(Stage::Compute), *hdr), ::testing::StartsWith("it does not wait for Compute"));
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
        EXPECT_NE(std::string(e.what()).find("no step 'nosuch'; its steps are: forward_ibl, skybox, tonemap"),
                  std::string::npos) << e.what();
    }
}

class GoldenAssertion : public ::testing::Test {
protected:
    // The test sets SKYGRAPH_UPDATE_GOLDEN itself; whatever the caller had is put back.
    void SetUp() override {
        if (const char* before = std::getenv("SKYGRAPH_UPDATE_GOLDEN")) saved_ = before;
        ::unsetenv("SKYGRAPH_UPDATE_GOLDEN");
        dir_ = fs::temp_directory_path() / ("skygraph_kit_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
    }
    void TearDown() override {
        fs::remove_all(dir_);
        if (saved_) ::setenv("SKYGRAPH_UPDATE_GOLDEN", saved_->c_str(), 1);
    }
    fs::path dir_;
    std::optional<std::string> saved_;
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
