// A Plan keeps every usage and barrier in two arrays that its passes view through spans, and
// its names in shared tables that they view (framework/compiler/plan_builder.hpp): copies
// must stand alone, names must outlive the graph, and edits (PlanEditor) must keep every view
// right.
#include "plan_editor.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>

#include <gtest/gtest.h>

#include <memory>
#include <optional>

namespace skygraph {
namespace {

// The shipped raster graph: slots, inserted clears, several barriers per batch.
Plan rasterPlan() {
    const GraphDesc g = loadGraphFile(std::string(SKYGRAPH_SOURCE_DIR) + "/graphs/raster.json",
                                      PassRegistry::withBuiltins());
    return compile(g);
}

TEST(PlanStorage, CopyStandsAloneAfterTheOriginalIsGone) {
    auto original = std::make_unique<Plan>(rasterPlan());
    const std::string expected = planToJson(*original).dump(1);
    bool hasSlot = false;
    for (const auto& p : original->passes())
        for (const auto& u : p.usages) hasSlot |= !u.slot.empty();
    ASSERT_TRUE(hasSlot) << "the graph must exercise slot names";

    Plan copy = *original;
    for (size_t i = 0; i < copy.passes().size(); ++i) {
        // No view of the copy may point into the original's arrays.
        if (!copy.passes()[i].usages.empty()) {
            EXPECT_NE(copy.passes()[i].usages.data(), original->passes()[i].usages.data()) << copy.passes()[i].name;
        }
        if (!copy.passes()[i].barriers.empty()) {
            EXPECT_NE(copy.passes()[i].barriers.data(), original->passes()[i].barriers.data()) << copy.passes()[i].name;
        }
    }
    original.reset();
    EXPECT_EQ(planToJson(copy).dump(1), expected);

    Plan assigned;
    assigned = copy;
    Plan moved = std::move(copy);
    EXPECT_EQ(planToJson(moved).dump(1), expected);
    EXPECT_EQ(planToJson(assigned).dump(1), expected);
}

// Names are views into tables the plan shares (the compiler's copy of the graph's names, and
// its own for slots and inserted clears): they must outlive the graph and every copy but one.
// Names past the small-string size live on the heap, where ASan sees a dangling view.
TEST(PlanStorage, NamesOutliveTheGraphAndEveryOtherCopy) {
    std::optional<Plan> plan;
    {
        const GraphDesc g = parseGraph(R"({"version": 1, "name": "names", "features": {}, "resources": {
            "accumulation_of_every_sample": {"type": "image2d", "format": "R16G16B16A16_SFLOAT",
                                             "extent": [8, 8], "clear": {"color": [0, 0, 0, 0]}},
            "presented_image": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8],
                                "final": "ShaderRead"}},
          "passes": [
            {"name": "trace_one_more_sample_per_pixel", "type": "Generic",
             "uses": {"accumulation_of_every_sample": "ReadWrite@Compute"}},
            {"name": "show_the_average", "type": "TonemappingPass",
             "uses": [{"resource": "accumulation_of_every_sample", "access": "Read", "stage": "Fragment",
                       "slot": "hdr"},
                      {"resource": "presented_image", "access": "Write", "stage": "ColorAttachment"}]}]})",
                                       "names.json", PassRegistry::withBuiltins());
        plan = compile(g);
    }
    const Plan copy = *plan;
    plan.reset();
    ASSERT_EQ(copy.passes().size(), 3u);
    EXPECT_EQ(copy.passes()[0].name, "clear accumulation_of_every_sample");
    EXPECT_EQ(copy.passes()[0].type, "Clear");
    EXPECT_EQ(copy.passes()[1].name, "trace_one_more_sample_per_pixel");
    EXPECT_EQ(copy.passes()[1].type, "Generic");
    EXPECT_EQ(copy.passes()[2].name, "show_the_average");
    EXPECT_EQ(copy.passes()[2].type, "TonemappingPass");
    ASSERT_EQ(copy.passes()[2].usages.size(), 2u);
    EXPECT_EQ(copy.passes()[2].usages[0].slot, "hdr");
    EXPECT_EQ(copy.passes()[2].usages[1].slot, "output");  // the unique slot it fits
    ASSERT_EQ(copy.resources().size(), 2u);
    EXPECT_EQ(copy.resources()[0].name, "accumulation_of_every_sample");
    EXPECT_EQ(copy.resources()[1].name, "presented_image");
}

// No slots and no inserted clears: the names view the graph's table alone.
TEST(PlanStorage, NamesOfAPlanWithoutSlotsOrClearsOutliveTheGraph) {
    std::optional<Plan> plan;
    {
        const GraphDesc g = parseGraph(R"({"version": 1, "name": "plain", "features": {}, "resources": {
            "an_image_with_a_name_past_the_small_string_size": {"type": "image2d", "format": "R8G8B8A8_UNORM",
                                                                "extent": [8, 8], "final": "ShaderRead"}},
          "passes": [{"name": "a_pass_with_a_name_past_the_small_string_size", "type": "Generic",
                      "uses": {"an_image_with_a_name_past_the_small_string_size": "Write@Compute"}}]})",
                                       "plain.json", PassRegistry::withBuiltins());
        plan = compile(g);
    }
    ASSERT_EQ(plan->passes().size(), 1u);
    EXPECT_EQ(plan->passes()[0].name, "a_pass_with_a_name_past_the_small_string_size");
    EXPECT_EQ(plan->passes()[0].type, "Generic");
    EXPECT_TRUE(plan->passes()[0].usages[0].slot.empty());
    ASSERT_EQ(plan->resources().size(), 1u);
    EXPECT_EQ(plan->resources()[0].name, "an_image_with_a_name_past_the_small_string_size");
}

// The most accesses a plan can have: every scheduled usage and a Clear per `clear` resource,
// here one resource used twice (a mip each), outside an attachment, in its first pass: one
// Clear, not two.
TEST(PlanStorage, AClearResourceUsedTwiceInItsFirstPassGetsOneClear) {
    const GraphDesc g = parseGraph(R"({"version": 1, "name": "twice", "features": {}, "resources": {
        "lut": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [8, 8], "mips": 2,
                "clear": {"color": [0, 0, 0, 0]}},
        "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "final": "ShaderRead"}},
      "passes": [{"name": "p", "type": "Generic", "uses": [
          {"resource": "lut", "access": "Read", "stage": "Compute", "mips": [0, 1]},
          {"resource": "lut", "access": "Read", "stage": "Fragment", "mips": [1, 1]},
          {"resource": "out", "access": "Write", "stage": "ColorAttachment"}]}]})",
                                   "twice.json", PassRegistry::withBuiltins());
    const Plan plan = compile(g);
    ASSERT_EQ(plan.passes().size(), 2u);
    EXPECT_EQ(plan.passes()[0].type, "Clear");
    EXPECT_EQ(plan.passes()[0].name, "clear lut");
    ASSERT_EQ(plan.passes()[0].usages.size(), 1u);
    EXPECT_EQ(plan.passes()[1].name, "p");
    EXPECT_EQ(plan.passes()[1].usages.size(), 3u);
}

TEST(PlanStorage, EditsStayInTheirPlanAndKeepLaterPassesIntact) {
    const Plan base = rasterPlan();
    // The first pass with at least two barriers, and some later pass with barriers.
    std::optional<size_t> edited;
    for (size_t p = 0; p < base.passes().size() && !edited; ++p)
        if (base.passes()[p].barriers.size() >= 2) edited = p;
    ASSERT_TRUE(edited);
    const size_t e = *edited;

    Plan plan = base;
    const VkPipelineStageFlags2 before = base.passes()[e].barriers[0].srcStages;
    detail::PlanEditor::barriersOf(plan, e)[0].srcStages = before ^ VK_PIPELINE_STAGE_2_HOST_BIT;
    EXPECT_EQ(plan.passes()[e].barriers[0].srcStages, before ^ VK_PIPELINE_STAGE_2_HOST_BIT);
    EXPECT_EQ(base.passes()[e].barriers[0].srcStages, before) << "the copy was edited, not the base";

    const Barrier second = plan.passes()[e].barriers[1];
    detail::PlanEditor::eraseBarrier(plan, e, 0);
    ASSERT_EQ(plan.passes()[e].barriers.size(), base.passes()[e].barriers.size() - 1);
    EXPECT_EQ(plan.passes()[e].barriers[0], second);
    for (size_t p = 0; p < plan.passes().size(); ++p) {
        if (p == e) continue;
        ASSERT_EQ(plan.passes()[p].barriers.size(), base.passes()[p].barriers.size()) << plan.passes()[p].name;
        for (size_t i = 0; i < plan.passes()[p].barriers.size(); ++i)
            EXPECT_EQ(plan.passes()[p].barriers[i], base.passes()[p].barriers[i]) << plan.passes()[p].name << " #" << i;
    }
    EXPECT_THROW(detail::PlanEditor::eraseBarrier(plan, e, plan.passes()[e].barriers.size()), std::out_of_range);

    // Emptying a batch leaves an empty view, and copying the edited plan keeps the edit.
    while (!plan.passes()[e].barriers.empty()) detail::PlanEditor::eraseBarrier(plan, e, 0);
    const Plan again = plan;
    EXPECT_TRUE(again.passes()[e].barriers.empty());
    EXPECT_EQ(planToJson(again).dump(1), planToJson(plan).dump(1));
}

}  // namespace
}  // namespace skygraph
