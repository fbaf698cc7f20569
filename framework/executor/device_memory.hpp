// Device memory that images and buffers are bound into: a resource's own allocation, or one
// heap of a plan's memory layout (Plan::memory()) for one frame slot, which several transient
// resources share. Everything bound to a DeviceMemory holds a reference to it, so it is freed
// only after the last image or buffer in it is destroyed, whichever owner (a plan state, a
// SharedImage) lets go last.
#pragma once

#include <skygraph/memory.hpp>
#include <skygraph/vk_handles.hpp>

#include <vulkan/vulkan_core.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

namespace skygraph::detail {

struct DeviceMemory {
    owned::Memory memory;
    VkDeviceSize bytes = 0;
    uint32_t type = 0;  ///< The memory type index it was allocated from.
    /// The device's Device::allocatedBytes() count, which holds `bytes` while this lives.
    std::atomic<uint64_t>* counted = nullptr;

    DeviceMemory() = default;
    DeviceMemory(const DeviceMemory&) = delete;
    DeviceMemory& operator=(const DeviceMemory&) = delete;
    ~DeviceMemory() {
        if (counted) counted->fetch_sub(bytes);
    }
};

/// Shared by everything bound to it; immutable once allocated.
using SharedMemory = std::shared_ptr<const DeviceMemory>;

/// Why a resource whose device requirements are `device` cannot be bound at `placement` in
/// memory of type `type` that holds `heap`, or empty when it can: its size must fit the
/// placement, the placement's offset must meet its alignment, the memory type must be one it
/// can live in, and the placement must lie inside the heap. A plan placed with another
/// memory model than the device's fails here.
[[nodiscard]] std::string placementMismatch(const VkMemoryRequirements& device, const MemoryPlacement& placement,
                                            const MemoryHeap& heap, uint32_t type);

}  // namespace skygraph::detail
