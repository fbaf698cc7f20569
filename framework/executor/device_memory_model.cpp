#include "device_memory_model.hpp"

#include <skygraph/device.hpp>

#include <algorithm>
#include <type_traits>

namespace skygraph::detail {

MemoryRequirements servingBothSharingModes(const MemoryRequirements& exclusive, const MemoryRequirements& concurrent,
                                           const std::string& resource, const std::string& device) {
    const uint32_t types = exclusive.memoryTypeBits & concurrent.memoryTypeBits;
    if (types == 0)
        throw ExecutorError("resource '" + resource + "': device '" + device +
                            "' has no DEVICE_LOCAL memory type for it both exclusive and shared concurrently; "
                            "nothing was allocated");
    // Alignments are powers of two (the spec's VkMemoryRequirements), so the larger is a
    // multiple of the smaller.
    return {std::max(exclusive.size, concurrent.size), std::max(exclusive.alignment, concurrent.alignment), types};
}

DeviceMemoryModel::DeviceMemoryModel(VkDevice device, VkPhysicalDevice physical, std::string name,
                                     const std::array<uint32_t, kQueueKinds>& queueFamilies)
    : physical_(physical), capacity_(DeviceCapacity::of(physical)), name_(std::move(name)),
      families_(distinctFamilies(queueFamilies)), device_(device) {
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(physical, &mem);
    for (uint32_t i = 0; i < mem.memoryTypeCount; ++i)
        if (mem.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) deviceLocalTypes_ |= 1u << i;
}

void DeviceMemoryModel::detach() noexcept {
    std::lock_guard lock(mutex_);
    device_ = VK_NULL_HANDLE;
}

uint64_t DeviceMemoryModel::bufferImageGranularity() const {
    std::lock_guard lock(mutex_);
    if (!device_)
        throw ExecutorError("the memory model of device '" + name_ + "' was asked after the device was destroyed");
    return capacity_.limits.bufferImageGranularity;
}

MemoryRequirements DeviceMemoryModel::requirements(const MemoryQuery& q) const {
    if (!q.resource) throw ExecutorError("a memory query without a resource");
    const ResourceDesc& d = *q.resource;
    const bool concurrent = mayBeConcurrent(d);
    const Key key = d.isImage() ? Key{true, concurrent, uint32_t(d.type), d.format.format, q.width, q.height, q.mips,
                                      q.layers, q.imageUsage, 0}
                                : Key{false, concurrent, 0, VK_FORMAT_UNDEFINED, 0, 0, 0, 0, q.bufferUsage,
                                      bufferBytes(d)};
    std::lock_guard lock(mutex_);
    if (!device_)
        throw ExecutorError("resource '" + d.name + "': the memory model of device '" + name_ +
                            "' was asked after the device was destroyed");
    if (const auto it = cache_.find(key); it != cache_.end()) return it->second;
    const MemoryRequirements answer = ask(q, concurrent);
    cache_.emplace(key, answer);
    return answer;
}

bool DeviceMemoryModel::mayBeConcurrent(const ResourceDesc& d) const noexcept {
    return families_.count >= 2 && d.sharing != Sharing::Exclusive;
}

MemoryRequirements DeviceMemoryModel::ask(const MemoryQuery& q, bool concurrent) const {
    const ResourceDesc& d = *q.resource;
    if (d.isImage()) {
        // Refused first: asking about an image the device cannot create is invalid usage.
        refuseImageBeyondLimits(capacity_, d, q.width, q.height, q.mips, q.layers, "");
        const VkImageCreateInfo ci = imageCreateInfo(d, q.width, q.height, q.mips, q.layers, q.imageUsage);
        refuseUnsupportedImage(physical_, d, ci);
        return askInSharingModes(d, ci, concurrent);
    }
    refuseBufferBeyondLimits(capacity_, d, q.bufferUsage);
    return askInSharingModes(d, bufferCreateInfo(d, q.bufferUsage), concurrent);
}

template <typename CreateInfo>
MemoryRequirements DeviceMemoryModel::askInSharingModes(const ResourceDesc& d, CreateInfo ci, bool concurrent) const {
    const MemoryRequirements exclusive = askAbout(d, ci);
    if (!concurrent) return exclusive;
    shareConcurrently(ci, families_);
    return servingBothSharingModes(exclusive, askAbout(d, ci), d.name, name_);
}

template <typename CreateInfo>
MemoryRequirements DeviceMemoryModel::askAbout(const ResourceDesc& d, const CreateInfo& ci) const {
    VkMemoryRequirements2 req{VK_STRUCTURE_TYPE_MEMORY_REQUIREMENTS_2};
    if constexpr (std::is_same_v<CreateInfo, VkImageCreateInfo>) {
        VkDeviceImageMemoryRequirements info{VK_STRUCTURE_TYPE_DEVICE_IMAGE_MEMORY_REQUIREMENTS};
        info.pCreateInfo = &ci;
        vkGetDeviceImageMemoryRequirements(device_, &info, &req);
    } else {
        VkDeviceBufferMemoryRequirements info{VK_STRUCTURE_TYPE_DEVICE_BUFFER_MEMORY_REQUIREMENTS};
        info.pCreateInfo = &ci;
        vkGetDeviceBufferMemoryRequirements(device_, &info, &req);
    }
    const VkMemoryRequirements& r = req.memoryRequirements;
    const uint32_t types = r.memoryTypeBits & deviceLocalTypes_;
    // (size 0: what lavapipe answers for a resource too large to make)
    if (r.size == 0)
        throw DeviceCapacityError("resource '" + d.name + "': device '" + name_ +
                                  "' reports no memory requirements for it; nothing was allocated", d.name);
    if (types == 0)
        throw ExecutorError("resource '" + d.name + "': device '" + name_ +
                            "' reports no DEVICE_LOCAL memory type for it; nothing was allocated");
    return {r.size, std::max<VkDeviceSize>(r.alignment, 1), types};
}

}  // namespace skygraph::detail
