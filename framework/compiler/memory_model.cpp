// The device-free memory estimate as a MemoryModel (its arithmetic is in memory_planner.hpp),
// and the usage flags both the compiler and the executor derive from a plan's usages.
#include "memory_planner.hpp"

#include <skygraph/memory.hpp>

#include <algorithm>
#include <functional>

namespace skygraph {
namespace {

class EstimatedMemory final : public MemoryModel {
public:
    MemoryRequirements requirements(const MemoryQuery& q) const override { return estimatedRequirements(q); }
    uint64_t bufferImageGranularity() const override { return estimate::kGranularity; }
    std::string name() const override { return "estimate"; }
};

}  // namespace

std::shared_ptr<const MemoryModel> estimatedMemory() {
    static const auto model = std::make_shared<const EstimatedMemory>();
    return model;
}

UsageFlags usageFlags(const UsageMode& u, bool image) noexcept {
    UsageFlags f;
    const BindAs as = resolvedBinding(u, image);
    switch (u.stage) {
        case Stage::ColorAttachment: f.image = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT; break;
        case Stage::DepthAttachment: f.image = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT; break;
        case Stage::Vertex:
        case Stage::Fragment:
        case Stage::Compute:
            if (as == BindAs::Sampled) {
                f.image = VK_IMAGE_USAGE_SAMPLED_BIT;
            } else if (as == BindAs::Uniform) {
                f.buffer = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
            } else {
                f.image = VK_IMAGE_USAGE_STORAGE_BIT;
                f.buffer = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
            }
            break;
        case Stage::VertexInput:
            f.buffer = as == BindAs::Index ? VK_BUFFER_USAGE_INDEX_BUFFER_BIT : VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
            break;
        case Stage::Indirect: f.buffer = VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT; break;
        case Stage::Transfer:
            // Images the executor makes can always be copied (kAlwaysUsable); images it is
            // given must say so.
            if (readsContents(u.access)) f.image |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
            if (writesContents(u.access)) f.image |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
            break;
    }
    return f;
}

MemoryLayout::MemoryLayout(const MemoryLayout& other)
    : heaps(other.heaps), placements(other.placements), strategy(other.strategy), model(other.model),
      granularity(other.granularity), unaliasedBytes(other.unaliasedBytes), peakLiveBytes(other.peakLiveBytes),
      sharedAcrossFrames(other.sharedAcrossFrames), aliasStorage_(other.aliasStorage_) {
    // Only views into `other`'s storage move to the copy's; a caller may have pointed a
    // placement at storage of its own, which the copy views as the original does. std::less
    // orders pointers into unrelated arrays too, where < would be undefined.
    const std::less<const uint32_t*> before;
    const uint32_t* begin = other.aliasStorage_.data();
    const uint32_t* end = begin + other.aliasStorage_.size();
    const auto rebased = [&](std::span<const uint32_t> v) -> std::span<const uint32_t> {
        if (v.empty()) return {};
        if (before(v.data(), begin) || !before(v.data(), end)) return v;
        return {aliasStorage_.data() + (v.data() - begin), v.size()};
    };
    for (MemoryPlacement& p : placements) {
        p.aliases = rebased(p.aliases);
        p.previousFrameAliases = rebased(p.previousFrameAliases);
    }
}

MemoryLayout& MemoryLayout::operator=(const MemoryLayout& other) {
    if (this != &other) *this = MemoryLayout(other);
    return *this;
}

bool operator==(const MemoryLayout& a, const MemoryLayout& b) {
    const auto samePlacement = [](const MemoryPlacement& x, const MemoryPlacement& y) {
        return x.resource == y.resource && x.heap == y.heap && x.offset == y.offset && x.bytes == y.bytes &&
               x.requirements == y.requirements && x.aliasable == y.aliasable &&
               std::equal(x.aliases.begin(), x.aliases.end(), y.aliases.begin(), y.aliases.end()) &&
               std::equal(x.previousFrameAliases.begin(), x.previousFrameAliases.end(),
                          y.previousFrameAliases.begin(), y.previousFrameAliases.end());
    };
    return a.heaps == b.heaps && a.strategy == b.strategy && a.model == b.model && a.granularity == b.granularity &&
           a.unaliasedBytes == b.unaliasedBytes && a.peakLiveBytes == b.peakLiveBytes &&
           a.sharedAcrossFrames == b.sharedAcrossFrames &&
           std::equal(a.placements.begin(), a.placements.end(), b.placements.begin(), b.placements.end(),
                      samePlacement);
}

const char* toString(MemoryStrategy s) noexcept {
    switch (s) {
        case MemoryStrategy::BestFitBySize: return "bestFitBySize";
        case MemoryStrategy::FirstUseOrder: return "firstUseOrder";
        case MemoryStrategy::Unaliased: return "unaliased";
    }
    return "?";
}

}  // namespace skygraph
