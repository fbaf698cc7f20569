// Device selection without Vulkan calls: what device.cpp gathered about each physical device
// goes in; why one cannot run skygraph (or present to the window's surface), and the error
// when none is chosen, come out. Pure, so that tests can reach every reason without a device.
#pragma once

#include <skygraph/graph.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph::detail {

struct QueueFamilyFacts {
    bool graphicsAndCompute = false;  ///< VK_QUEUE_GRAPHICS_BIT and VK_QUEUE_COMPUTE_BIT
    bool timestamps = false;          ///< timestampValidBits > 0
    bool presents = false;            ///< vkGetPhysicalDeviceSurfaceSupportKHR (with a surface)
    bool compute = false;             ///< VK_QUEUE_COMPUTE_BIT
    /// VK_QUEUE_TRANSFER_BIT and copies of any texel region (minImageTransferGranularity 1x1x1);
    /// graphics and compute families transfer too.
    bool transfers = false;
    uint32_t queueCount = 1;
};

struct PhysicalDeviceFacts {
    uint32_t apiVersion = 0;
    bool pushDescriptor = false;    ///< VK_KHR_push_descriptor
    bool synchronization2 = false;  ///< the Vulkan 1.3 feature
    /// Depth-only layouts (DEPTH_ATTACHMENT_OPTIMAL, DEPTH_READ_ONLY_OPTIMAL) in plans.
    bool separateDepthStencilLayouts = false;
    /// Plans on several queues order their submits with a timeline semaphore per queue.
    bool timelineSemaphore = false;
    bool swapchain = false;         ///< VK_KHR_swapchain
    /// The first of DeviceOptions::deviceExtensions the device lacks; empty when it has them all.
    std::string missingExtension;
    std::vector<QueueFamilyFacts> families;
};

/// Why a device with `facts` cannot run skygraph, or empty when it can; then `family` is the
/// first graphics+compute family with timestamps (that also presents, when `presenting`).
std::string unsuitableReason(const PhysicalDeviceFacts& facts, bool presenting, uint32_t& family);

/// A queue of the device: its family and its index in the family.
struct QueueChoice {
    uint32_t family = 0;
    uint32_t index = 0;
    friend bool operator==(const QueueChoice&, const QueueChoice&) = default;
};

/// The queue each queue kind (indexed by QueueKind) submits to. Graphics is `graphicsFamily`'s
/// first queue. With `separate`, compute prefers a family without graphics (dedicated async
/// compute), then a second queue of the graphics family; transfer prefers a family with
/// neither graphics nor compute (a DMA engine), then the compute queue. A kind that finds
/// nothing shares the graphics queue, as every kind does without `separate`.
std::array<QueueChoice, kQueueKinds> chooseQueues(const std::vector<QueueFamilyFacts>& families,
                                                  uint32_t graphicsFamily, bool separate);

/// One physical device as Device::create saw it.
struct DeviceCandidate {
    size_t index = 0;
    std::string name;      ///< VkPhysicalDeviceProperties::deviceName
    std::string type;      ///< "CPU", "discrete GPU", ...
    bool matched = false;  ///< DeviceOptions::device selects it (every device when empty)
    std::string reason;    ///< unsuitableReason's; empty: usable
};

/// The ExecutorError message when no candidate was chosen. `filter` is DeviceOptions::device.
/// No device matching the filter: one line listing the devices. One device selected (by the
/// filter, or the only one): one line naming it (index and name) and why it cannot be used.
/// Several: each with its reason, a line each.
std::string noDeviceMessage(std::string_view filter, bool presenting, const std::vector<DeviceCandidate>& devices);

}  // namespace skygraph::detail
