// The device's answer to "how much memory does this resource need": what Device::memoryModel()
// gives the compiler, so that a plan's placements are made with the requirements of exactly
// the images and buffers the Renderer creates (resource_creation.hpp).
#pragma once

#include "resource_creation.hpp"

#include <skygraph/memory.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <tuple>

namespace skygraph::detail {

/// The requirements of a resource that may be created either way: the larger size and
/// alignment, and the memory types both allow. Throws ExecutorError naming `resource` and
/// `device` when no type allows both.
[[nodiscard]] MemoryRequirements servingBothSharingModes(const MemoryRequirements& exclusive,
                                                         const MemoryRequirements& concurrent,
                                                         const std::string& resource, const std::string& device);

/// Asks the device with vkGetDeviceImageMemoryRequirements / vkGetDeviceBufferMemoryRequirements
/// (Vulkan 1.3; nothing is created to ask) about the create info the Renderer would use for a
/// query, after refusing what the device cannot create (resource_creation.hpp's checks, so
/// the driver is never asked about an invalid image). memoryTypeBits keep only the
/// DEVICE_LOCAL types, the ones the Renderer allocates from. Answers are cached per query.
/// Where the device's queues span several families it asks twice, exclusive and concurrent over
/// them (not for a resource declared `"sharing": "exclusive"`), and answers what serves both:
/// memory is placed before the queue planner decides which transients the families share
/// concurrently, and the Renderer creates those concurrent.
///
/// Thread-safe: every call locks one mutex, which the driver call runs under, so detach()
/// cannot destroy the device during a call. The Device owns it and calls detach() before it
/// destroys its VkDevice; compile options may share it beyond that, and requirements() and
/// bufferImageGranularity() then throw ExecutorError. Not copyable.
class DeviceMemoryModel final : public MemoryModel {
public:
    /// Borrows `device`, valid until detach(). Reads the physical device's limits and memory
    /// types once. `queueFamilies`: Device::queueFamilies(), which concurrent resources are
    /// shared over.
    DeviceMemoryModel(VkDevice device, VkPhysicalDevice physical, std::string name,
                      const std::array<uint32_t, kQueueKinds>& queueFamilies);
    DeviceMemoryModel(const DeviceMemoryModel&) = delete;
    DeviceMemoryModel& operator=(const DeviceMemoryModel&) = delete;

    /// Throws DeviceCapacityError naming the resource when it is past the device's limits
    /// (refuseImageBeyondLimits / refuseBufferBeyondLimits) or the device reports no memory for
    /// it (too large to make); UnsupportedResourceError when the device cannot create it
    /// otherwise (refuseUnsupportedImage); ExecutorError when none of its memory types is DEVICE_LOCAL (for both
    /// sharing modes, where it asks about both), or once the device is gone.
    [[nodiscard]] MemoryRequirements requirements(const MemoryQuery& query) const override;
    /// The device's bufferImageGranularity. Throws ExecutorError once the device is gone.
    [[nodiscard]] uint64_t bufferImageGranularity() const override;
    /// The device's name; answered after the device is gone too, for messages.
    [[nodiscard]] std::string name() const override { return name_; }

    /// The memory types transients are allocated from: those with DEVICE_LOCAL.
    [[nodiscard]] uint32_t deviceLocalTypes() const noexcept { return deviceLocalTypes_; }
    /// The device is about to be destroyed: nothing calls into it after this returns.
    void detach() noexcept;

private:
    /// Everything of a query that the create infos asked about depend on, and whether the
    /// concurrent one is asked too.
    using Key = std::tuple<bool, bool, uint32_t, VkFormat, uint32_t, uint32_t, uint32_t, uint32_t, uint32_t, uint64_t>;
    /// Whether the queue planner may share a resource of this declaration concurrently.
    [[nodiscard]] bool mayBeConcurrent(const ResourceDesc& d) const noexcept;
    // Under mutex_: `concurrent` is mayBeConcurrent()'s answer for the query's resource.
    [[nodiscard]] MemoryRequirements ask(const MemoryQuery& query, bool concurrent) const;
    /// `ci` as it is, and when `concurrent` also shared concurrently, combined.
    template <typename CreateInfo>
    [[nodiscard]] MemoryRequirements askInSharingModes(const ResourceDesc& d, CreateInfo ci, bool concurrent) const;
    template <typename CreateInfo>
    [[nodiscard]] MemoryRequirements askAbout(const ResourceDesc& d, const CreateInfo& ci) const;

    const VkPhysicalDevice physical_;
    const DeviceCapacity capacity_;
    const std::string name_;
    const ConcurrentFamilies families_;
    uint32_t deviceLocalTypes_ = 0;
    mutable std::mutex mutex_;
    VkDevice device_;  ///< Guarded by mutex_; VK_NULL_HANDLE once detached.
    mutable std::map<Key, MemoryRequirements> cache_;  ///< Guarded by mutex_.
};

}  // namespace skygraph::detail
