#include <skygraph/plan_format.hpp>
#include <skygraph/testing/barrier_matchers.hpp>

#include <stdexcept>

namespace skygraph::testkit {
namespace {

// The kit's own reading of which pipeline stages a graph stage runs in: a barrier "from" a
// stage has all of these in its source scope (after the umbrella stages are expanded).
constexpr VkPipelineStageFlags2 stagesOf(Stage stage) {
    switch (stage) {
        case Stage::ColorAttachment: return VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
        case Stage::DepthAttachment:
            return VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
        case Stage::Vertex: return VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT;
        case Stage::Fragment: return VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
        case Stage::Compute: return VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
        case Stage::Transfer:  // a graph's Transfer usage may be a copy, a blit, a clear or a resolve
            return VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_BLIT_BIT | VK_PIPELINE_STAGE_2_CLEAR_BIT |
                   VK_PIPELINE_STAGE_2_RESOLVE_BIT;
        case Stage::VertexInput:
            return VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT | VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT;
        case Stage::Indirect: return VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT;
    }
    return 0;
}

/// `mask` with its umbrella stages replaced by what they stand for (the spec's "Pipeline
/// Stages": ALL_COMMANDS, ALL_GRAPHICS, ALL_TRANSFER, VERTEX_INPUT, PRE_RASTERIZATION_SHADERS).
VkPipelineStageFlags2 expanded(VkPipelineStageFlags2 mask) {
    constexpr VkPipelineStageFlags2 kVertexInput =
        VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT | VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT;
    constexpr VkPipelineStageFlags2 kPreRasterization =
        VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_TESSELLATION_CONTROL_SHADER_BIT |
        VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT | VK_PIPELINE_STAGE_2_GEOMETRY_SHADER_BIT;
    constexpr VkPipelineStageFlags2 kTransfer = stagesOf(Stage::Transfer);
    constexpr VkPipelineStageFlags2 kGraphics =
        VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | kVertexInput | kPreRasterization |
        VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT |
        VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    if (mask & VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT) return ~VkPipelineStageFlags2(0);
    if (mask & VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT) mask |= kGraphics;
    if (mask & VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT) mask |= kTransfer;
    if (mask & VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT) mask |= kVertexInput;
    if (mask & VK_PIPELINE_STAGE_2_PRE_RASTERIZATION_SHADERS_BIT) mask |= kPreRasterization;
    return mask;
}

bool covers(VkPipelineStageFlags2 mask, Stage stage) {
    const VkPipelineStageFlags2 needed = stagesOf(stage);
    return (expanded(mask) & needed) == needed;
}

const char* stageName(Stage stage) {
    switch (stage) {
        case Stage::ColorAttachment: return "ColorAttachment";
        case Stage::DepthAttachment: return "DepthAttachment";
        case Stage::Vertex: return "Vertex";
        case Stage::Fragment: return "Fragment";
        case Stage::Compute: return "Compute";
        case Stage::Transfer: return "Transfer";
        case Stage::VertexInput: return "VertexInput";
        case Stage::Indirect: return "Indirect";
    }
    return "?";
}

constexpr VkAccessFlags2 kWrites = VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                                   VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                                   VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT |
                                   VK_ACCESS_2_HOST_WRITE_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;

const char* hazardName(Hazard h) {
    switch (h) {
        case Hazard::ReadAfterWrite: return "read-after-write";
        case Hazard::WriteAfterWrite: return "write-after-write";
        case Hazard::WriteAfterRead: return "write-after-read";
    }
    return "?";
}

/// Whether the barrier orders that hazard. A write-after-read needs only an execution
/// dependency (its source stages are checked by from()), so its source access does not matter:
/// a barrier after a read and a write resolves both.
bool resolves(const Barrier& b, Hazard h) {
    const bool srcWrites = (b.srcAccess & kWrites) != 0;
    const bool dstReads = (b.dstAccess & ~kWrites) != 0;
    const bool dstWrites = (b.dstAccess & kWrites) != 0 || b.oldLayout != b.newLayout;
    switch (h) {
        case Hazard::ReadAfterWrite: return srcWrites && dstReads;
        case Hazard::WriteAfterWrite: return srcWrites && dstWrites;
        case Hazard::WriteAfterRead: return dstWrites;
    }
    return false;
}

std::string masks(const Barrier& b) {
    const auto join = [](const std::vector<std::string>& names) {
        std::string s;
        for (const std::string& n : names) s += (s.empty() ? "" : "|") + n;
        return s.empty() ? std::string("NONE") : s;
    };
    return join(stageMaskNames(b.srcStages)) + " / " + join(accessMaskNames(b.srcAccess)) + " -> " +
           join(stageMaskNames(b.dstStages)) + " / " + join(accessMaskNames(b.dstAccess)) + ", " +
           layoutName(b.oldLayout) + " -> " + layoutName(b.newLayout);
}

std::vector<NamedBarrier> named(const Plan& plan, std::span<const Barrier> barriers) {
    std::vector<NamedBarrier> out;
    for (const Barrier& b : barriers)
        out.push_back({b.kind == BarrierKind::Memory || b.resource >= plan.resources().size()
                           ? std::string()
                           : std::string(plan.resources()[b.resource].name),
                       b});
    return out;
}

}  // namespace

void PrintTo(const NamedBarrier& b, std::ostream* os) {
    *os << (b.resource.empty() ? "memory" : b.resource) << ": " << masks(b.barrier);
}

std::vector<NamedBarrier> barriersBefore(const Plan& plan, std::string_view pass) {
    std::string steps;
    for (const PlannedPass& p : plan.passes()) {
        if (p.name == pass) return named(plan, p.barriers);
        steps += (steps.empty() ? "" : ", ") + std::string(p.name);
    }
    throw std::out_of_range("the plan has no step '" + std::string(pass) + "'; its steps are: " + steps);
}

std::vector<NamedBarrier> finalBarriers(const Plan& plan) { return named(plan, plan.finalBarriers()); }

class BarrierMatcher : public ::testing::MatcherInterface<const NamedBarrier&> {
public:
    explicit BarrierMatcher(BarrierExpectation e) : e_(std::move(e)) {}

    bool MatchAndExplain(const NamedBarrier& b, ::testing::MatchResultListener* listener) const override {
        const auto miss = [&](const std::string& why) {
            *listener << why;
            return false;
        };
        if (b.resource != e_.resource_) return miss("it is on " + (b.resource.empty() ? "memory" : b.resource));
        if (e_.hazard_ && !resolves(b.barrier, *e_.hazard_))
            return miss(std::string("it is not a ") + hazardName(*e_.hazard_) + ": " + masks(b.barrier));
        if (e_.from_ && !covers(b.barrier.srcStages, *e_.from_))
            return miss(std::string("it does not wait for ") + stageName(*e_.from_) + ": " + masks(b.barrier));
        if (e_.to_ && !covers(b.barrier.dstStages, *e_.to_))
            return miss(std::string("it does not block ") + stageName(*e_.to_) + ": " + masks(b.barrier));
        if (e_.oldLayout_ && b.barrier.oldLayout != *e_.oldLayout_)
            return miss("it transitions from " + layoutName(b.barrier.oldLayout));
        if (e_.newLayout_ && b.barrier.newLayout != *e_.newLayout_)
            return miss("it leaves the image in " + layoutName(b.barrier.newLayout));
        return true;
    }

    void DescribeTo(std::ostream* os) const override {
        *os << "is a barrier on " << e_.resource_;
        if (e_.hazard_) *os << ", a " << hazardName(*e_.hazard_);
        if (e_.from_) *os << ", from " << stageName(*e_.from_);
        if (e_.to_) *os << ", to " << stageName(*e_.to_);
        if (e_.oldLayout_) *os << ", from layout " << layoutName(*e_.oldLayout_);
        if (e_.newLayout_) *os << ", into " << layoutName(*e_.newLayout_);
    }

private:
    BarrierExpectation e_;
};

BarrierExpectation::operator ::testing::Matcher<const NamedBarrier&>() const {
    return ::testing::MakeMatcher(new BarrierMatcher(*this));
}

}  // namespace skygraph::testkit
