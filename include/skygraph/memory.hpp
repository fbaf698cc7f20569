// Transient memory: what a device needs to hold a resource, and where the compiler places each
// transient resource (docs/memory.md). Resources that live in disjoint parts of the frame share
// memory; the plan's aliasing barriers order one's uses before the next one's.
#pragma once

#include <skygraph/graph.hpp>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace skygraph {

/// What a device needs to hold one resource: VkMemoryRequirements.
struct MemoryRequirements {
    uint64_t size = 0;
    uint64_t alignment = 1;          ///< A power of two.
    uint32_t memoryTypeBits = ~0u;   ///< The memory types it can live in.

    friend bool operator==(const MemoryRequirements&, const MemoryRequirements&) = default;
};

/// A resource as the executor creates it: what a MemoryModel is asked about. `resource` is
/// borrowed for the call.
struct MemoryQuery {
    const ResourceDesc* resource = nullptr;  ///< Its type, format and (buffers) size.
    uint32_t width = 1, height = 1;          ///< Resolved at the output size.
    uint32_t mips = 1, layers = 1;
    VkImageUsageFlags imageUsage = 0;        ///< Images: every usage the plan needs of it.
    VkBufferUsageFlags bufferUsage = 0;      ///< Buffers.
};

/// Where the compiler learns how much memory a resource needs. The executor's comes from the
/// device (Device::memoryModel(), vkGetDeviceImageMemoryRequirements); compiles without a
/// device use estimatedMemory(). Implementations must be safe to call from several threads,
/// as compile() is.
class MemoryModel {
public:
    virtual ~MemoryModel() = default;
    /// Throws std::runtime_error (or a subclass) when it cannot answer.
    [[nodiscard]] virtual MemoryRequirements requirements(const MemoryQuery& query) const = 0;
    /// VkPhysicalDeviceLimits::bufferImageGranularity: how far apart buffers and optimal
    /// images must stay unless they alias.
    [[nodiscard]] virtual uint64_t bufferImageGranularity() const = 0;
    /// For plans and messages: "estimate", or the device's name.
    [[nodiscard]] virtual std::string name() const = 0;
};

/// The device-free estimate (docs/memory.md, "Requirements"): texels tightly packed, every
/// mip level of every layer, a 64 KiB alignment and size granule for images, 256 bytes for
/// buffers, one memory type, a bufferImageGranularity of 1 KiB. Shared and immutable.
[[nodiscard]] std::shared_ptr<const MemoryModel> estimatedMemory();

/// The image and buffer usage flags that a usage needs of its resource: the one mapping of
/// graph usages to VkImageUsageFlags / VkBufferUsageFlags, which the compiler asks the memory
/// model about and the executor creates resources with.
struct UsageFlags {
    VkImageUsageFlags image = 0;
    VkBufferUsageFlags buffer = 0;
};
[[nodiscard]] UsageFlags usageFlags(const UsageMode& usage, bool image) noexcept;
/// What every image and buffer the executor makes can do besides: be copied from and to
/// (clears, clobbering, read-backs, uploads).
inline constexpr UsageFlags kAlwaysUsable{VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                          VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT};

/// How transient resources are placed in their heaps (docs/memory.md, "Placement").
enum class MemoryStrategy : uint8_t {
    /// Largest first, each into the tightest gap left by the resources already placed that
    /// live at the same time. The default.
    BestFitBySize,
    /// In order of first use, each into the tightest free block of memory that no live
    /// resource holds (an online allocator: what a frame-by-frame pool achieves).
    FirstUseOrder,
    /// No sharing: every transient resource gets a range of its own (`--no-alias`).
    Unaliased,
};

/// One block of memory of the executor's: one VkDeviceMemory that the frames in flight share,
/// or one per frame in flight (MemoryLayout::sharedAcrossFrames).
struct MemoryHeap {
    uint64_t bytes = 0;
    /// The memory types every resource in it can live in.
    uint32_t memoryTypeBits = ~0u;
    /// It holds buffers and optimal images together, so every placement in it starts and
    /// ends on a multiple of bufferImageGranularity (the spec's padded ranges are then the
    /// placements themselves).
    bool granular = false;

    friend bool operator==(const MemoryHeap&, const MemoryHeap&) = default;
};

/// Where one transient resource lives.
struct MemoryPlacement {
    uint32_t resource = 0;  ///< Index into Plan::resources().
    uint32_t heap = 0;      ///< Index into MemoryLayout::heaps.
    uint64_t offset = 0;
    uint64_t bytes = 0;     ///< Its requirements' size (a multiple of the granularity when granular).
    MemoryRequirements requirements;
    /// Whether it may share memory at all (the file's `"alias": false` and --no-alias say not).
    bool aliasable = true;
    /// The resources whose memory it takes over: for every byte of its range, the last
    /// resource earlier in the frame that held it (indices into Plan::resources(), ascending).
    /// Its first barriers wait for their last uses: the aliasing barriers. Views storage of
    /// the MemoryLayout that holds this placement: valid while that layout lives and is not
    /// assigned to (a move keeps it valid).
    std::span<const uint32_t> aliases;
    /// With frames in flight sharing the heaps (CompileOptions::shareTransientsAcrossFrames):
    /// for the bytes of its range that no earlier resource of the frame held, the resources
    /// that held them last in the previous frame, itself included where it did. Its first
    /// barriers wait for their last uses there too. Views storage as `aliases` does.
    std::span<const uint32_t> previousFrameAliases;
};

namespace detail {
struct MemoryLayoutBuilder;  // the implementation's own access; not part of the API
}

/// The plan's transient memory: heaps and placements, and the figures to judge them by.
/// Copies are deep: a copy's placements view its own copy of the alias storage the compiler
/// wrote (a placement pointed at storage of the caller's keeps viewing that).
struct MemoryLayout {
    MemoryLayout() = default;
    MemoryLayout(const MemoryLayout& other);
    MemoryLayout& operator=(const MemoryLayout& other);
    MemoryLayout(MemoryLayout&&) noexcept = default;
    MemoryLayout& operator=(MemoryLayout&&) noexcept = default;
    ~MemoryLayout() = default;

    std::vector<MemoryHeap> heaps;
    /// One per transient resource (not external, not exported), in Plan::resources() order.
    std::vector<MemoryPlacement> placements;
    MemoryStrategy strategy = MemoryStrategy::BestFitBySize;
    std::string model;            ///< MemoryModel::name() of the requirements' source.
    uint64_t granularity = 1;     ///< The model's bufferImageGranularity.
    /// The sum of the placements' bytes: what the transients need without aliasing.
    uint64_t unaliasedBytes = 0;
    /// The most bytes of transients live during any one pass: no placement can use less.
    uint64_t peakLiveBytes = 0;

    /// Whether the frames in flight share the heaps (CompileOptions::shareTransientsAcrossFrames):
    /// the executor then allocates them once, not once per frame in flight.
    bool sharedAcrossFrames = false;

    /// The sum of the heaps' bytes: what the executor allocates (per frame in flight unless
    /// sharedAcrossFrames).
    [[nodiscard]] uint64_t heapBytes() const noexcept {
        uint64_t sum = 0;
        for (const MemoryHeap& h : heaps) sum += h.bytes;
        return sum;
    }

    /// Equal heaps, placements (aliases compared by value) and figures.
    friend bool operator==(const MemoryLayout& a, const MemoryLayout& b);

private:
    friend struct detail::MemoryLayoutBuilder;
    std::vector<uint32_t> aliasStorage_;  // every placement's aliases, one after another
};

/// "bestFitBySize", "firstUseOrder", "unaliased"; static storage, never null.
[[nodiscard]] const char* toString(MemoryStrategy s) noexcept;

}  // namespace skygraph
