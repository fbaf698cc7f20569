// How the executor creates the image or buffer of a plan resource, and what a device can hold:
// one definition that the Renderer creates resources with and the device's memory model asks
// the driver about (DeviceMemoryModel), so that what was asked is what gets created.
#pragma once

#include <skygraph/graph.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <string>

namespace skygraph::detail {

/// A plan image: 2D, optimal tiling, one sample, cube compatible for cubes, created UNDEFINED.
[[nodiscard]] VkImageCreateInfo imageCreateInfo(const ResourceDesc& d, uint32_t width, uint32_t height,
                                                uint32_t mips, uint32_t layers, VkImageUsageFlags usage) noexcept;
/// A plan buffer of `bufferBytes(d)`.
[[nodiscard]] VkBufferCreateInfo bufferCreateInfo(const ResourceDesc& d, VkBufferUsageFlags usage) noexcept;
/// The different queue families among `families` (Device::queueFamilies()), the list a
/// concurrently shared resource is created with.
struct ConcurrentFamilies {
    std::array<uint32_t, kQueueKinds> indices{};
    uint32_t count = 0;
};
[[nodiscard]] ConcurrentFamilies distinctFamilies(const std::array<uint32_t, kQueueKinds>& families) noexcept;
/// Makes `ci` (an image or buffer create info) VK_SHARING_MODE_CONCURRENT over `families`
/// when there are two or more; one family needs no sharing. `families` must outlive `ci`.
template <typename CreateInfo>
void shareConcurrently(CreateInfo& ci, const ConcurrentFamilies& families) noexcept {
    if (families.count < 2) return;
    ci.sharingMode = VK_SHARING_MODE_CONCURRENT;
    ci.queueFamilyIndexCount = families.count;
    ci.pQueueFamilyIndices = families.indices.data();
}
/// At least 4 bytes: a buffer cannot be empty, and vkCmdFillBuffer writes whole words.
[[nodiscard]] VkDeviceSize bufferBytes(const ResourceDesc& d) noexcept;
/// Every mip of every layer with its texels tightly packed: what is checked against the memory
/// cap before the device is asked anything.
[[nodiscard]] VkDeviceSize packedBytes(const ResourceDesc& d, uint32_t width, uint32_t height, uint32_t mips,
                                       uint32_t layers) noexcept;
/// "1.25 GiB".
[[nodiscard]] std::string gib(VkDeviceSize bytes);

/// What a device lets a plan ask of it, read once from the physical device.
struct DeviceCapacity {
    VkPhysicalDeviceLimits limits{};
    /// Half the largest device-local heap (docs/reliability.md: the other half is left to
    /// pipelines, staging and other programs); 0 when the device reports none.
    VkDeviceSize memoryCap = 0;
    /// The most one vkAllocateMemory may ask for (maxMemoryAllocationSize); 0 when unknown.
    VkDeviceSize maxAllocation = 0;
    [[nodiscard]] static DeviceCapacity of(VkPhysicalDevice physical);
};

/// Throws DeviceCapacityError naming the resource and the limit, ending in "nothing was allocated",
/// for an image the device cannot hold: beyond its dimension or layer limits, or alone over
/// the memory cap; `at` follows the extent in the message (e.g. " at output 64x64").
void refuseImageBeyondLimits(const DeviceCapacity& capacity, const ResourceDesc& d, uint32_t width,
                             uint32_t height, uint32_t mips, uint32_t layers, const std::string& at);
/// Throws UnsupportedResourceError naming the resource when the device cannot create `ci` (its
/// format with that usage, flags, extent, mips and layers).
void refuseUnsupportedImage(VkPhysicalDevice physical, const ResourceDesc& d, const VkImageCreateInfo& ci);
/// Throws DeviceCapacityError for a buffer beyond the device's binding ranges for its usage, or alone
/// over the memory cap.
void refuseBufferBeyondLimits(const DeviceCapacity& capacity, const ResourceDesc& d, VkBufferUsageFlags usage);

}  // namespace skygraph::detail
