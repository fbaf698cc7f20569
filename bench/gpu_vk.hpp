// Small Vulkan helpers for the GPU benchmarks (gpu_frame_bench): device-local buffers and
// images, and a timer that records one command buffer between two timestamps. Bench-only:
// the executor keeps its own helpers, and nothing here is part of the embedding API.
#pragma once

#include <skygraph/device.hpp>
#include <skygraph/vk_handles.hpp>

#include <vulkan/vulkan_core.h>

#include <functional>
#include <vector>

namespace skygraph::gpubench {

/// A device-local buffer and its memory, owned.
struct DeviceBuffer {
    owned::Buffer buffer;
    owned::Memory memory;
    VkDeviceSize size = 0;
};

/// Creates a DEVICE_LOCAL buffer of `size` bytes. Throws ExecutorError.
[[nodiscard]] DeviceBuffer createDeviceBuffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage);

/// A device-local 2D image (one mip, one layer, optimal tiling) with a color view, owned.
struct DeviceImage {
    owned::Image image;
    owned::Memory memory;
    owned::ImageView view;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{};
};

/// Creates a DEVICE_LOCAL image in layout UNDEFINED. Throws ExecutorError.
[[nodiscard]] DeviceImage createDeviceImage(Device& device, VkFormat format, VkExtent2D extent,
                                            VkImageUsageFlags usage);

/// Records work into a one-shot command buffer, submits it and waits; optionally brackets it
/// with ALL_COMMANDS timestamps and returns the GPU time. Owns its pool, command buffer,
/// query pool and fence; borrows the device, which must outlive it.
class GpuTimer {
public:
    explicit GpuTimer(Device& device);
    ~GpuTimer();
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    /// Runs `record` once on the GPU and returns its time in milliseconds. `prologue`, when
    /// given, is recorded before the first timestamp (which waits for it): untimed set-up in
    /// the same submission, e.g. evicting the cache.
    double time(const std::function<void(VkCommandBuffer)>& record,
                const std::function<void(VkCommandBuffer)>& prologue = {});
    /// Runs `record` once on the GPU, untimed (set-up work).
    void run(const std::function<void(VkCommandBuffer)>& record);

private:
    double submit(const std::function<void(VkCommandBuffer)>& record,
                  const std::function<void(VkCommandBuffer)>& prologue, bool timed);

    Device& device_;
    owned::CommandPool pool_;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    owned::QueryPool queries_;
    owned::Fence fence_;
};

/// Median of `values` (the mean of the middle two for an even count); 0 when empty.
[[nodiscard]] double median(std::vector<double> values);
/// The value at fraction `q` (0..1) of the sorted values (nearest rank); 0 when empty.
[[nodiscard]] double quantile(std::vector<double> values, double q);

/// A full pipeline barrier (ALL_COMMANDS, memory read/write both ways), for bench set-up
/// work where precision does not matter.
void fullBarrier(VkCommandBuffer cmd);
/// Transitions a whole single-mip color image, after every earlier command.
void transitionImage(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to);

}  // namespace skygraph::gpubench
