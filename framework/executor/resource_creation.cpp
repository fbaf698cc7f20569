#include "resource_creation.hpp"

#include "texel_encoding.hpp"
#include "vk_util.hpp"

#include <skygraph/device.hpp>

#include <algorithm>
#include <cstdio>

namespace skygraph::detail {

VkImageCreateInfo imageCreateInfo(const ResourceDesc& d, uint32_t width, uint32_t height, uint32_t mips,
                                  uint32_t layers, VkImageUsageFlags usage) noexcept {
    VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ci.flags = d.type == ResourceType::Cube ? VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT : 0;
    ci.imageType = VK_IMAGE_TYPE_2D;
    ci.format = d.format.format;
    ci.extent = {width, height, 1};
    ci.mipLevels = mips;
    ci.arrayLayers = layers;
    ci.samples = VK_SAMPLE_COUNT_1_BIT;
    ci.tiling = VK_IMAGE_TILING_OPTIMAL;
    ci.usage = usage;
    ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    return ci;
}

ConcurrentFamilies distinctFamilies(const std::array<uint32_t, kQueueKinds>& families) noexcept {
    ConcurrentFamilies out;
    for (const uint32_t f : families)
        if (std::find(out.indices.begin(), out.indices.begin() + out.count, f) == out.indices.begin() + out.count)
            out.indices[out.count++] = f;
    return out;
}

VkDeviceSize bufferBytes(const ResourceDesc& d) noexcept { return std::max<VkDeviceSize>(d.sizeBytes, 4); }

VkBufferCreateInfo bufferCreateInfo(const ResourceDesc& d, VkBufferUsageFlags usage) noexcept {
    VkBufferCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    ci.size = bufferBytes(d);
    ci.usage = usage;
    ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    return ci;
}

VkDeviceSize packedBytes(const ResourceDesc& d, uint32_t width, uint32_t height, uint32_t mips,
                         uint32_t layers) noexcept {
    if (!d.isImage()) return bufferBytes(d);
    const VkDeviceSize texel = std::max(1u, copyTexelBytes(d.format));
    VkDeviceSize bytes = 0;
    for (uint32_t m = 0; m < std::max(1u, mips); ++m)
        bytes += VkDeviceSize(std::max(1u, width >> m)) * std::max(1u, height >> m) * texel * std::max(1u, layers);
    return bytes;
}

std::string gib(VkDeviceSize bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f GiB", static_cast<double>(bytes) / double(1ull << 30));
    return text;
}

DeviceCapacity DeviceCapacity::of(VkPhysicalDevice physical) {
    DeviceCapacity c;
    VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props.pNext = &maintenance3;
    vkGetPhysicalDeviceProperties2(physical, &props);
    c.limits = props.properties.limits;
    c.maxAllocation = maintenance3.maxMemoryAllocationSize;
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(physical, &mem);
    VkDeviceSize heap = 0;
    for (uint32_t i = 0; i < mem.memoryHeapCount; ++i)
        if (mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) heap = std::max(heap, mem.memoryHeaps[i].size);
    c.memoryCap = heap / 2;
    return c;
}

namespace {

void refuseOverCap(const DeviceCapacity& capacity, const ResourceDesc& d, VkDeviceSize bytes) {
    if (capacity.memoryCap != 0 && bytes > capacity.memoryCap)
        throw DeviceCapacityError("resource '" + d.name + "' needs " + gib(bytes) + ", over the memory cap of " +
                            gib(capacity.memoryCap) +
                            " (half the device's largest device-local heap); nothing was allocated", d.name);
}

}  // namespace

void refuseImageBeyondLimits(const DeviceCapacity& capacity, const ResourceDesc& d, uint32_t width, uint32_t height,
                             uint32_t mips, uint32_t layers, const std::string& at) {
    const VkPhysicalDeviceLimits& limits = capacity.limits;
    const bool cube = d.type == ResourceType::Cube;
    const uint32_t most = cube ? limits.maxImageDimensionCube : limits.maxImageDimension2D;
    if (width > most || height > most)
        throw DeviceCapacityError("resource '" + d.name + "': " + std::to_string(width) + "x" + std::to_string(height) +
                            " exceeds the device's " + (cube ? "maxImageDimensionCube" : "maxImageDimension2D") +
                            " (" + std::to_string(most) + ")" + at + "; nothing was allocated", d.name);
    if (layers > limits.maxImageArrayLayers)
        throw DeviceCapacityError("resource '" + d.name + "': " + std::to_string(layers) +
                            " layers exceed the device's maxImageArrayLayers (" +
                            std::to_string(limits.maxImageArrayLayers) + "); nothing was allocated", d.name);
    refuseOverCap(capacity, d, packedBytes(d, width, height, mips, layers));
}

void refuseUnsupportedImage(VkPhysicalDevice physical, const ResourceDesc& d, const VkImageCreateInfo& ci) {
    VkImageFormatProperties fp;
    if (vkGetPhysicalDeviceImageFormatProperties(physical, ci.format, ci.imageType, ci.tiling, ci.usage, ci.flags,
                                                 &fp) != VK_SUCCESS ||
        fp.maxMipLevels < ci.mipLevels || fp.maxArrayLayers < ci.arrayLayers ||
        fp.maxExtent.width < ci.extent.width || fp.maxExtent.height < ci.extent.height) {
        throw UnsupportedResourceError("resource '" + d.name + "': the device cannot create a " +
                                           std::string(d.format.name) + " image of " +
                                           std::to_string(ci.extent.width) + "x" + std::to_string(ci.extent.height) +
                                           " with the usages the plan needs (" + vk::imageUsageText(ci.usage) + ")",
                                       d.name);
    }
}

void refuseBufferBeyondLimits(const DeviceCapacity& capacity, const ResourceDesc& d, VkBufferUsageFlags usage) {
    const VkPhysicalDeviceLimits& limits = capacity.limits;
    if ((usage & VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) && d.sizeBytes > limits.maxStorageBufferRange)
        throw DeviceCapacityError("resource '" + d.name + "': a storage buffer of " + std::to_string(d.sizeBytes) +
                            " bytes exceeds the device's maxStorageBufferRange (" +
                            std::to_string(limits.maxStorageBufferRange) + "); nothing was allocated", d.name);
    if ((usage & VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT) && d.sizeBytes > limits.maxUniformBufferRange)
        throw DeviceCapacityError("resource '" + d.name + "': a uniform buffer of " + std::to_string(d.sizeBytes) +
                            " bytes exceeds the device's maxUniformBufferRange (" +
                            std::to_string(limits.maxUniformBufferRange) + "); nothing was allocated", d.name);
    refuseOverCap(capacity, d, bufferBytes(d));
}

}  // namespace skygraph::detail
