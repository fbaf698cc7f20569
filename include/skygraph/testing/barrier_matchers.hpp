// GoogleMock matchers for the barriers of a plan (library skygraph::testing): what a reviewer
// says of a barrier, in the graph's words, checked against the plan.
//
//     using namespace skygraph::testkit;
//     EXPECT_THAT(barriersBefore(plan, "tonemap"),
//                 ::testing::Contains(barrier("hdr_color").readAfterWrite()
//                                         .from(skygraph::Stage::ColorAttachment)
//                                         .to(skygraph::Stage::Fragment)
//                                         .into(VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)));
#pragma once

#include <skygraph/plan.hpp>
#include <skygraph/usage.hpp>

#include <gmock/gmock.h>

#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph::testkit {

/// A plan barrier with the name of its resource (empty for a global memory barrier). A copy;
/// it views nothing of the plan.
struct NamedBarrier {
    std::string resource;
    Barrier barrier;
};
void PrintTo(const NamedBarrier& b, std::ostream* os);

/// The barriers recorded before plan step `pass` (a pass's name, or an inserted step's such as
/// "clear hdr_color", as plan text prints it). Throws std::out_of_range naming the pass and the
/// steps there are.
[[nodiscard]] std::vector<NamedBarrier> barriersBefore(const Plan& plan, std::string_view pass);
/// The barriers after the last step (Plan::finalBarriers()).
[[nodiscard]] std::vector<NamedBarrier> finalBarriers(const Plan& plan);

/// The hazard a barrier resolves, from its masks: a write made visible to a read
/// (ReadAfterWrite: a write in the source access, a read in the destination access), or to a
/// write or layout transition (WriteAfterWrite); or a write or transition ordered after
/// earlier reads (WriteAfterRead: an execution dependency, whatever the source access).
enum class Hazard : uint8_t { ReadAfterWrite, WriteAfterWrite, WriteAfterRead };

/// What a barrier must be; every part left unset matches anything. Each setter returns a new
/// expectation (a value: nothing dangles). Converts to a matcher of NamedBarrier whose
/// description and mismatch explanation name each part.
class BarrierExpectation {
public:
    explicit BarrierExpectation(std::string resource) : resource_(std::move(resource)) {}
    [[nodiscard]] BarrierExpectation readAfterWrite() const { return with(&BarrierExpectation::hazard_, Hazard::ReadAfterWrite); }
    [[nodiscard]] BarrierExpectation writeAfterWrite() const { return with(&BarrierExpectation::hazard_, Hazard::WriteAfterWrite); }
    [[nodiscard]] BarrierExpectation writeAfterRead() const { return with(&BarrierExpectation::hazard_, Hazard::WriteAfterRead); }
    /// Its source stages include every pipeline stage of `stage` (the usage's stage in the
    /// graph file: both fragment test stages for DepthAttachment, COPY, BLIT, CLEAR and RESOLVE
    /// for Transfer), umbrella stages such as ALL_COMMANDS expanded.
    [[nodiscard]] BarrierExpectation from(Stage stage) const { return with(&BarrierExpectation::from_, stage); }
    /// Its destination stages include every pipeline stage of `stage`, as from().
    [[nodiscard]] BarrierExpectation to(Stage stage) const { return with(&BarrierExpectation::to_, stage); }
    /// It transitions from `layout`.
    [[nodiscard]] BarrierExpectation fromLayout(VkImageLayout layout) const {
        return with(&BarrierExpectation::oldLayout_, layout);
    }
    /// It leaves the image in `layout` (a transition, or a barrier that keeps that layout).
    [[nodiscard]] BarrierExpectation into(VkImageLayout layout) const {
        return with(&BarrierExpectation::newLayout_, layout);
    }

    operator ::testing::Matcher<const NamedBarrier&>() const;  // NOLINT(google-explicit-constructor)

private:
    friend class BarrierMatcher;
    template <typename Member, typename Value>
    BarrierExpectation with(Member member, Value value) const {
        BarrierExpectation copy = *this;
        copy.*member = value;
        return copy;
    }
    std::string resource_;
    std::optional<Hazard> hazard_;
    std::optional<Stage> from_, to_;
    std::optional<VkImageLayout> oldLayout_, newLayout_;
};

/// Starts an expectation of a barrier on `resource`.
[[nodiscard]] inline BarrierExpectation barrier(std::string resource) { return BarrierExpectation(std::move(resource)); }

}  // namespace skygraph::testkit
