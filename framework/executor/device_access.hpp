// Internal: a Device's private state for the executor's own sources (the renderer reads the
// device's properties and extension entry points from it). Not part of the public API.
#pragma once

#include <skygraph/device.hpp>

namespace skygraph {

struct DeviceAccess {
    /// The device's state (vk_util.hpp defines it); valid while `device` lives.
    [[nodiscard]] static Device::Impl& impl(Device& device) noexcept { return *device.impl_; }
};

}  // namespace skygraph
