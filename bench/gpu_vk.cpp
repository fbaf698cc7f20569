// Bench-only Vulkan helpers (see gpu_vk.hpp).
#include "gpu_vk.hpp"

#include "vk_util.hpp"  // the executor's check() and findMemoryType()

#include <algorithm>
#include <cmath>

namespace skygraph::gpubench {

using vk::check;

namespace {

owned::Memory allocate(Device& device, const VkMemoryRequirements& req) {
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = vk::findMemoryType(device.physicalDevice(), req.memoryTypeBits,
                                            VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VkDeviceMemory memory;
    check(vkAllocateMemory(device.device(), &ai, nullptr, &memory), "vkAllocateMemory");
    return owned::Memory(device.device(), memory);
}

}  // namespace

DeviceBuffer createDeviceBuffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage) {
    DeviceBuffer b;
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = size;
    bi.usage = usage;
    bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkBuffer buffer;
    check(vkCreateBuffer(device.device(), &bi, nullptr, &buffer), "vkCreateBuffer");
    b.buffer = owned::Buffer(device.device(), buffer);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device.device(), buffer, &req);
    b.memory = allocate(device, req);
    check(vkBindBufferMemory(device.device(), buffer, b.memory.get(), 0), "vkBindBufferMemory");
    b.size = size;
    return b;
}

DeviceImage createDeviceImage(Device& device, VkFormat format, VkExtent2D extent, VkImageUsageFlags usage) {
    DeviceImage img;
    VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ii.imageType = VK_IMAGE_TYPE_2D;
    ii.format = format;
    ii.extent = {extent.width, extent.height, 1};
    ii.mipLevels = 1;
    ii.arrayLayers = 1;
    ii.samples = VK_SAMPLE_COUNT_1_BIT;
    ii.tiling = VK_IMAGE_TILING_OPTIMAL;
    ii.usage = usage;
    ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImage image;
    check(vkCreateImage(device.device(), &ii, nullptr, &image), "vkCreateImage");
    img.image = owned::Image(device.device(), image);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device.device(), image, &req);
    img.memory = allocate(device, req);
    check(vkBindImageMemory(device.device(), image, img.memory.get(), 0), "vkBindImageMemory");
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = image;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = format;
    vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView view;
    check(vkCreateImageView(device.device(), &vi, nullptr, &view), "vkCreateImageView");
    img.view = owned::ImageView(device.device(), view);
    img.format = format;
    img.extent = extent;
    return img;
}

GpuTimer::GpuTimer(Device& device) : device_(device) {
    const VkDevice vkd = device.device();
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = device.queueFamily();
    VkCommandPool pool;
    check(vkCreateCommandPool(vkd, &pci, nullptr, &pool), "vkCreateCommandPool");
    pool_ = owned::CommandPool(vkd, pool);
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    check(vkAllocateCommandBuffers(vkd, &ai, &cmd_), "vkAllocateCommandBuffers");
    VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qci.queryCount = 2;
    VkQueryPool queries;
    check(vkCreateQueryPool(vkd, &qci, nullptr, &queries), "vkCreateQueryPool");
    queries_ = owned::QueryPool(vkd, queries);
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    check(vkCreateFence(vkd, &fci, nullptr, &fence), "vkCreateFence");
    fence_ = owned::Fence(vkd, fence);
}

GpuTimer::~GpuTimer() { vkDeviceWaitIdle(device_.device()); }

double GpuTimer::time(const std::function<void(VkCommandBuffer)>& record,
                      const std::function<void(VkCommandBuffer)>& prologue) {
    return submit(record, prologue, true);
}

void GpuTimer::run(const std::function<void(VkCommandBuffer)>& record) { submit(record, {}, false); }

double GpuTimer::submit(const std::function<void(VkCommandBuffer)>& record,
                        const std::function<void(VkCommandBuffer)>& prologue, bool timed) {
    const VkDevice vkd = device_.device();
    check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd_, &bi), "vkBeginCommandBuffer");
    if (prologue) {
        prologue(cmd_);
        fullBarrier(cmd_);
    }
    if (timed) {
        vkCmdResetQueryPool(cmd_, queries_.get(), 0, 2);
        // ALL_COMMANDS on both sides: the first waits for everything earlier in this buffer
        // (the prologue), the second for everything recorded, so the interval is the recorded
        // work alone.
        vkCmdWriteTimestamp2(cmd_, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries_.get(), 0);
    }
    record(cmd_);
    if (timed) vkCmdWriteTimestamp2(cmd_, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries_.get(), 1);
    check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
    VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cbi.commandBuffer = cmd_;
    VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    si.commandBufferInfoCount = 1;
    si.pCommandBufferInfos = &cbi;
    const VkFence fence = fence_.get();
    check(vkResetFences(vkd, 1, &fence), "vkResetFences");
    check(vkQueueSubmit2(device_.queue(), 1, &si, fence), "vkQueueSubmit2");
    check(vkWaitForFences(vkd, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    if (!timed) return 0.0;
    uint64_t ts[2]{};
    check(vkGetQueryPoolResults(vkd, queries_.get(), 0, 2, sizeof(ts), ts, 8,
                                VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    return static_cast<double>(ts[1] - ts[0]) * device_.timestampPeriodNs() / 1.0e6;
}

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double quantile(std::vector<double> values, double q) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const auto rank = static_cast<size_t>(std::ceil(q * static_cast<double>(values.size())));
    return values[std::clamp<size_t>(rank, 1, values.size()) - 1];
}

void fullBarrier(VkCommandBuffer cmd) {
    VkMemoryBarrier2 mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    mb.srcStageMask = mb.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    mb.srcAccessMask = mb.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.memoryBarrierCount = 1;
    di.pMemoryBarriers = &mb;
    vkCmdPipelineBarrier2(cmd, &di);
}

void transitionImage(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to) {
    VkImageMemoryBarrier2 ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    ib.srcStageMask = ib.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    ib.srcAccessMask = ib.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
    ib.oldLayout = from;
    ib.newLayout = to;
    ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    ib.image = image;
    ib.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.imageMemoryBarrierCount = 1;
    di.pImageMemoryBarriers = &ib;
    vkCmdPipelineBarrier2(cmd, &di);
}

}  // namespace skygraph::gpubench
