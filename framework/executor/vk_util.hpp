// Internal helpers for the executor: error checking and small RAII owners of Vulkan handles.
#pragma once

#include "device_access.hpp"

#include <skygraph/device.hpp>
#include <skygraph/vk_handles.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace skygraph::vk {

[[nodiscard]] const char* resultName(VkResult r) noexcept;
/// "96x64", for messages.
[[nodiscard]] std::string extentText(VkExtent2D e);
/// "COLOR_ATTACHMENT | STORAGE", for messages; "none" for 0.
[[nodiscard]] std::string imageUsageText(VkImageUsageFlags usage);

/// Throws ExecutorError naming the call when `r` is not VK_SUCCESS.
inline void check(VkResult r, const char* what) {
    if (r != VK_SUCCESS) {
        throw ExecutorError(std::string(what) + " failed: " + resultName(r));
    }
}

/// Device extension entry points the executor uses, loaded once per device.
struct DeviceFunctions {
    PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet = nullptr;
    PFN_vkCmdBeginDebugUtilsLabelEXT cmdBeginLabel = nullptr;  ///< null without debug utils
    PFN_vkCmdEndDebugUtilsLabelEXT cmdEndLabel = nullptr;
    PFN_vkSetDebugUtilsObjectNameEXT setObjectName = nullptr;
};

}  // namespace skygraph::vk

namespace skygraph::owned {

struct DestroySemaphore {
    static void destroy(VkDevice device, VkSemaphore semaphore) noexcept { vkDestroySemaphore(device, semaphore, nullptr); }
};
struct DestroySwapchain {
    static void destroy(VkDevice device, VkSwapchainKHR swapchain) noexcept {
        vkDestroySwapchainKHR(device, swapchain, nullptr);
    }
};
using Semaphore = Owned<VkSemaphore, DestroySemaphore>;
using Swapchain = Owned<VkSwapchainKHR, DestroySwapchain>;

}  // namespace skygraph::owned

namespace skygraph::vk {

/// A new binary semaphore of `device`; throws ExecutorError when it cannot be made.
[[nodiscard]] inline owned::Semaphore makeBinarySemaphore(VkDevice device) {
    VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VkSemaphore raw;
    check(vkCreateSemaphore(device, &sci, nullptr, &raw), "vkCreateSemaphore");
    return owned::Semaphore(device, raw);
}

/// Index of a memory type with `required` properties among `typeBits`; throws if none.
[[nodiscard]] uint32_t findMemoryType(VkPhysicalDevice physical, uint32_t typeBits,
                                      VkMemoryPropertyFlags required);

}  // namespace skygraph::vk

namespace skygraph {

namespace detail {
class DeviceMemoryModel;  // device_memory_model.hpp
}

struct Device::Impl {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    VkSurfaceKHR surface = VK_NULL_HANDLE;  ///< DeviceOptions::presentation's; destroyed before the instance.
    uint32_t queueFamily = 0;
    /// The queue, its family, and whether it writes timestamps, per queue kind (indexed by
    /// QueueKind); kinds without a queue of their own hold the graphics queue.
    std::array<VkQueue, kQueueKinds> queues{};
    std::array<uint32_t, kQueueKinds> families{};
    std::array<bool, kQueueKinds> timestamps{};
    /// vkResetQueryPool from the host (hostQueryReset): timestamp queries written on several
    /// queues are reset before any of them runs, not by the first submit.
    bool hostQueryReset = false;
    std::string name;
    bool validation = false;
    bool logMessages = true;
    float timestampPeriod = 1.0f;
    VkPhysicalDeviceProperties properties{};
    vk::DeviceFunctions fn;
    /// Device::memoryModel(); detached by finish(), before the device goes.
    std::shared_ptr<detail::DeviceMemoryModel> memoryModel;
    /// Device::allocatedBytes(): each DeviceMemory adds its size and takes it back when freed.
    std::atomic<uint64_t> allocatedBytes{0};

    // Message counting; the callback may run on any thread.
    mutable std::mutex mutex;
    uint32_t count = 0;
    std::vector<ValidationMessage> kept;
    uint32_t performanceCount = 0;
    std::vector<ValidationMessage> performanceKept;
    uint32_t layerVersion = 0;  ///< The validation layer's specVersion; 0 without validation.

    /// Live objects made from this device, per DeviceUser (detail::DeviceUse counts them).
    std::array<std::atomic<uint32_t>, kDeviceUserKinds> users{};
    /// Held while a DeviceUse is counted in and while Device::finish() checks `users` and
    /// destroys the device: one made on another thread is either counted before the check or
    /// finds the device gone. Not `mutex`: destroying the device calls the message callback.
    std::mutex usersMutex;
    /// "1 Renderer and 2 SharedImages", or empty when none lives.
    [[nodiscard]] std::string liveUsers() const;

    /// Device::finish: waits, destroys the device and the surface (the messenger stays).
    void finish();
    ~Impl();
};

}  // namespace skygraph
