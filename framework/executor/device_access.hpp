// Internal: a Device's private state for the executor's own sources (the renderer reads the
// device's properties and extension entry points from it). Not part of the public API.
#pragma once

#include <skygraph/device.hpp>

namespace skygraph {

struct DeviceAccess {
    /// The device's state type, for the executor's sources that hold or pass it.
    using Impl = Device::Impl;

    /// The device's state (vk_util.hpp defines it); valid while `device` lives.
    [[nodiscard]] static Impl& impl(Device& device) noexcept { return *device.impl_; }
};

}  // namespace skygraph
