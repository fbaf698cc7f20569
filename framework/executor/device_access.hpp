// Internal: a Device's private state for the executor's own sources (the renderer reads the
// device's properties and extension entry points from it). Not part of the public API.
#pragma once

#include <skygraph/device.hpp>

#include <cstddef>
#include <cstdint>

namespace skygraph {

/// What is made from a Device and destroys Vulkan objects with it, so must go first.
enum class DeviceUser : uint8_t { Renderer, Swapchain, StagingBuffer, SharedImage };
inline constexpr size_t kDeviceUserKinds = 4;

struct DeviceAccess {
    /// The device's state type, for the executor's sources that hold or pass it.
    using Impl = Device::Impl;

    /// The device's state (vk_util.hpp defines it); valid while `device` lives.
    [[nodiscard]] static Impl& impl(Device& device) noexcept { return *device.impl_; }
};

namespace detail {
/// Counts one DeviceUser of a device while it lives, so that Device::finish() can refuse to
/// destroy the device under it and the Device's destructor can say what it destroyed first.
/// Declared first in its owner, so that it ends after the owner's Vulkan objects, and begins
/// before any is made: it throws ExecutorError once the device is finished.
class DeviceUse {
public:
    DeviceUse(DeviceAccess::Impl& device, DeviceUser user);
    ~DeviceUse();
    DeviceUse(const DeviceUse&) = delete;
    DeviceUse& operator=(const DeviceUse&) = delete;

private:
    DeviceAccess::Impl& device_;
    DeviceUser user_;
};
}  // namespace detail

}  // namespace skygraph
