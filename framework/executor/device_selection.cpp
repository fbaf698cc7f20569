// Device selection's reasons and error messages (device_selection.hpp); no Vulkan calls.
#include "device_selection.hpp"

#include <vulkan/vulkan_core.h>

#include <algorithm>
#include <optional>

namespace skygraph::detail {

std::string unsuitableReason(const PhysicalDeviceFacts& facts, bool presenting, uint32_t& family) {
    if (facts.apiVersion < VK_API_VERSION_1_3) return "does not support Vulkan 1.3";
    if (!facts.pushDescriptor) return "lacks VK_KHR_push_descriptor";
    if (!facts.synchronization2) return "lacks synchronization2";
    if (!facts.separateDepthStencilLayouts) return "lacks separateDepthStencilLayouts";
    if (!facts.timelineSemaphore) return "lacks timelineSemaphore";
    if (presenting && !facts.swapchain) return "cannot present: it lacks VK_KHR_swapchain";
    if (!facts.missingExtension.empty())
        return "lacks " + facts.missingExtension + ", which DeviceOptions::deviceExtensions asks for";
    bool renders = false;
    for (size_t i = 0; i < facts.families.size(); ++i) {
        const QueueFamilyFacts& f = facts.families[i];
        if (!f.graphicsAndCompute || !f.timestamps) continue;
        renders = true;
        if (!presenting || f.presents) {
            family = static_cast<uint32_t>(i);
            return {};
        }
    }
    if (renders) return "cannot present to the surface: no graphics+compute queue family of it presents there";
    return "has no graphics+compute queue with timestamps";
}

std::array<QueueChoice, kQueueKinds> chooseQueues(const std::vector<QueueFamilyFacts>& families,
                                                  uint32_t graphicsFamily, bool separate) {
    const QueueChoice graphics{graphicsFamily, 0};
    std::array<QueueChoice, kQueueKinds> chosen{graphics, graphics, graphics};
    if (!separate) return chosen;
    const auto firstFamily = [&](auto&& suits) -> std::optional<uint32_t> {
        for (uint32_t i = 0; i < families.size(); ++i)
            if (i != graphicsFamily && suits(families[i])) return i;
        return std::nullopt;
    };
    auto& compute = chosen[static_cast<size_t>(QueueKind::Compute)];
    if (const auto f = firstFamily([](const QueueFamilyFacts& q) { return q.compute && !q.graphicsAndCompute; }))
        compute = {*f, 0};
    else if (families.at(graphicsFamily).queueCount > 1)
        compute = {graphicsFamily, 1};
    auto& transfer = chosen[static_cast<size_t>(QueueKind::Transfer)];
    if (const auto f = firstFamily([](const QueueFamilyFacts& q) { return q.transfers && !q.compute; }))
        transfer = {*f, 0};
    else
        transfer = compute;
    return chosen;
}

namespace {

std::string named(const DeviceCandidate& d) { return std::to_string(d.index) + " '" + d.name + "'"; }

}  // namespace

std::string noDeviceMessage(std::string_view filter, bool presenting, const std::vector<DeviceCandidate>& devices) {
    if (devices.empty()) return "no Vulkan physical devices found";
    const std::string byFilter = "--device '" + std::string(filter) + "'";
    std::vector<const DeviceCandidate*> matched;
    for (const DeviceCandidate& d : devices)
        if (d.matched) matched.push_back(&d);
    if (matched.empty()) {
        std::string msg = "no Vulkan device matches " + byFilter + "; available devices:";
        for (size_t i = 0; i < devices.size(); ++i)
            msg += (i ? ", " : " ") + std::to_string(devices[i].index) + ": " + devices[i].name + " (" + devices[i].type + ")";
        return msg;
    }
    if (matched.size() == 1) {
        const DeviceCandidate& d = *matched.front();
        if (!filter.empty()) return byFilter + " selects Vulkan device " + named(d) + ", which " + d.reason;
        if (devices.size() == 1) return "the only Vulkan device, " + named(d) + ", " + d.reason;
    }
    std::string msg = "no suitable Vulkan device";
    if (!filter.empty()) msg += " matches " + byFilter;
    if (presenting) msg += " to present to the window";
    msg += ":";
    for (const DeviceCandidate* d : matched) msg += "\n  " + named(*d) + " (" + d->type + ") " + d->reason;
    if (matched.size() < devices.size()) {
        msg += "\navailable devices:";
        for (const DeviceCandidate& d : devices) msg += "\n  " + std::to_string(d.index) + ": " + d.name + " (" + d.type + ")";
    }
    return msg;
}

}  // namespace skygraph::detail
