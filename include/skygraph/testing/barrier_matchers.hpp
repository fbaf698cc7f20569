// GoogleMock matchers for the barriers of a plan (library skygraph::testing): what a reviewer
// says of a barrier, in the graph's words, checked against the plan.
//
//     using namespace skygraph::testing;
//     EXPECT_THAT(barriersBefore(plan, "tonemap"),
//                 Contains(barrier("hdr_color").readAfterWrite()
//                              .from(Stage::ColorAttachment).to(Stage::Fragment)
//                              .into(VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)));
#pragma once

#include <skygraph/plan.hpp>
#include <skygraph/usage.hpp>

#include <gmock/gmock.h>

#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph::testing {

/// A plan barrier with the name of its resource (empty for a global memory barrier). A copy;
/// it views nothing of the plan.
struct NamedBarrier {
    std::string resource;
    Barrier barrier;
};
void PrintTo(const NamedBarrier& b, std::ostream* os);

/// The barriers recorded before plan step `pass` (a pass's name, or an inserted step's such as
/// "clear_hdr_color"). Throws std::out_of_range naming the pass and the steps there are.
[[nodiscard]] std::vector<NamedBarrier> barriersBefore(const Plan& plan, std::string_view pass);
/// The barriers after the last step (Plan::finalBarriers()).
[[nodiscard]] std::vector<NamedBarrier> finalBarriers(const Plan& plan);

/// The hazard a barrier resolves, from its access masks: a write made visible to a read, to a
/// write, or (no source access) an execution dependency before a write or transition.
enum class Hazard : uint8_t { ReadAfterWrite, WriteAfterWrite, WriteAfterRead };

/// What a barrier must be; every part left unset matches anything. Converts to a matcher of
/// NamedBarrier whose description and mismatch explanation name each part.
class BarrierExpectation {
public:
    explicit BarrierExpectation(std::string resource) : resource_(std::move(resource)) {}
    BarrierExpectation& readAfterWrite() { hazard_ = Hazard::ReadAfterWrite; return *this; }
    BarrierExpectation& writeAfterWrite() { hazard_ = Hazard::WriteAfterWrite; return *this; }
    BarrierExpectation& writeAfterRead() { hazard_ = Hazard::WriteAfterRead; return *this; }
    /// Its source stages include those of `stage` (the usage's stage in the graph file).
    BarrierExpectation& from(Stage stage) { from_ = stage; return *this; }
    /// Its destination stages include those of `stage`.
    BarrierExpectation& to(Stage stage) { to_ = stage; return *this; }
    /// It transitions from `layout`.
    BarrierExpectation& fromLayout(VkImageLayout layout) { oldLayout_ = layout; return *this; }
    /// It leaves the image in `layout` (a transition, or a barrier that keeps that layout).
    BarrierExpectation& into(VkImageLayout layout) { newLayout_ = layout; return *this; }

    operator ::testing::Matcher<const NamedBarrier&>() const;  // NOLINT(google-explicit-constructor)

private:
    friend class BarrierMatcher;
    std::string resource_;
    std::optional<Hazard> hazard_;
    std::optional<Stage> from_, to_;
    std::optional<VkImageLayout> oldLayout_, newLayout_;
};

/// Starts an expectation of a barrier on `resource`.
[[nodiscard]] inline BarrierExpectation barrier(std::string resource) { return BarrierExpectation(std::move(resource)); }

}  // namespace skygraph::testing
