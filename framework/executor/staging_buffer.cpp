// StagingBuffer: host-visible memory that an UploadPass copies from. Its memory counts in
// Device::allocatedBytes() like every allocation the executor makes.
#include "device_access.hpp"
#include "device_memory.hpp"
#include "vk_util.hpp"

#include <skygraph/staging_buffer.hpp>

#include <string>

namespace skygraph {

struct StagingBuffer::Impl {
    explicit Impl(DeviceAccess::Impl& owner) : use(owner, DeviceUser::StagingBuffer) {}
    detail::DeviceUse use;
    detail::DeviceMemory memory;  ///< declared before the buffer: freed after it
    owned::Buffer buffer;
    std::byte* mapped = nullptr;
    VkDeviceSize size = 0;
    VkDevice device = VK_NULL_HANDLE;
};

std::shared_ptr<StagingBuffer> StagingBuffer::create(Device& device, VkDeviceSize bytes) {
    if (bytes == 0) throw ExecutorError("StagingBuffer::create: 0 bytes");
    DeviceAccess::Impl& d = DeviceAccess::impl(device);
    auto impl = std::make_unique<Impl>(d);
    impl->size = bytes;
    impl->device = d.device;
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = bytes;
    bci.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    VkBuffer raw;
    vk::check(vkCreateBuffer(d.device, &bci, nullptr, &raw), "vkCreateBuffer (staging buffer)");
    impl->buffer = owned::Buffer(d.device, raw);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(d.device, raw, &req);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = vk::findMemoryType(
        d.physical, req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    VkDeviceMemory memory;
    if (const VkResult r = vkAllocateMemory(d.device, &mai, nullptr, &memory); r != VK_SUCCESS)
        throw ExecutorError("staging buffer: vkAllocateMemory of " + std::to_string(req.size) +
                            " bytes failed: " + vk::resultName(r));
    impl->memory.memory = owned::Memory(d.device, memory);
    impl->memory.bytes = req.size;
    impl->memory.type = mai.memoryTypeIndex;
    impl->memory.counted = &d.allocatedBytes;
    d.allocatedBytes.fetch_add(req.size);
    vk::check(vkBindBufferMemory(d.device, raw, memory, 0), "vkBindBufferMemory (staging buffer)");
    void* mapped = nullptr;
    vk::check(vkMapMemory(d.device, memory, 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory (staging buffer)");
    impl->mapped = static_cast<std::byte*>(mapped);
    return std::shared_ptr<StagingBuffer>(new StagingBuffer(std::move(impl)));
}

StagingBuffer::StagingBuffer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
StagingBuffer::~StagingBuffer() = default;

std::span<std::byte> StagingBuffer::bytes() noexcept { return {impl_->mapped, size_t(impl_->size)}; }
std::span<const std::byte> StagingBuffer::bytes() const noexcept { return {impl_->mapped, size_t(impl_->size)}; }
VkDeviceSize StagingBuffer::size() const noexcept { return impl_->size; }
VkBuffer StagingBuffer::buffer() const noexcept { return impl_->buffer.get(); }
VkDevice StagingBuffer::device() const noexcept { return impl_->device; }

}  // namespace skygraph
