// Renderer::Impl: device memory. A transient that the plan places (Plan::memory()) is bound
// into its heap at its offset, one allocation per heap per frame slot (or one in all, when the
// frames share the heaps); every other resource gets memory of its own. The memory is shared
// by what is bound to it (device_memory.hpp).
#include "renderer_access.hpp"
#include "renderer_impl.hpp"

#include <cstdio>

namespace skygraph {

using namespace detail;

namespace detail {

std::string placementMismatch(const VkMemoryRequirements& device, const MemoryPlacement& p, const MemoryHeap& heap,
                              uint32_t type) {
    std::string why;
    const auto add = [&](const std::string& reason) { why += (why.empty() ? "" : "; ") + reason; };
    if (device.size > p.bytes)
        add("the device needs " + std::to_string(device.size) + " bytes, its placement has " + std::to_string(p.bytes));
    if (device.alignment > 1 && p.offset % device.alignment != 0)
        add("its offset " + std::to_string(p.offset) + " is not a multiple of the device's alignment " +
            std::to_string(device.alignment));
    if (type >= 32 || ((device.memoryTypeBits >> type) & 1u) == 0) {
        char bits[16];
        std::snprintf(bits, sizeof bits, "0x%x", device.memoryTypeBits);
        add("it cannot live in its heap's memory type " + std::to_string(type) + " (the device allows " + bits + ")");
    }
    if (p.offset + p.bytes > heap.bytes)
        add("its placement ends at byte " + std::to_string(p.offset + p.bytes) + ", past its heap's " +
            std::to_string(heap.bytes));
    return why;
}

}  // namespace detail

CompiledGraph Renderer::Impl::forDevice(CompiledGraph compiled, std::optional<VkExtent2D> extent) const {
    std::shared_ptr<const MemoryModel> model = device.memoryModel();
    const auto families = device.queueFamilies();
    // A plan whose passes all run on the graphics queue is the same for every queue family.
    const bool familiesMatter = compiled.plan().submits().size() > 1;
    const bool resizes =
        extent && (compiled.outputWidth() != extent->width || compiled.outputHeight() != extent->height);
    if (!resizes && compiled.options().memory == model &&
        (!familiesMatter || compiled.options().queueFamilies == families))
        return compiled;
    CompileOptions onDevice = compiled.options();
    onDevice.memory = std::move(model);
    onDevice.queueFamilies = families;
    if (resizes) {
        onDevice.outputWidth = extent->width;
        onDevice.outputHeight = extent->height;
    }
    try {
        return CompiledGraph(compiled.graph(), std::move(onDevice));
    } catch (const GraphError& e) {
        if (resizes) throw ExecutorError("presenting at " + vk::extentText(*extent) + ": " + e.what());
        throw ExecutorError("graph '" + compiled.graph().name + "' with the memory requirements and queue families of device '" +
                            device.name() + "': " + e.what());
    }
}

SharedMemory Renderer::Impl::allocate(VkDeviceSize bytes, uint32_t typeBits, VkMemoryPropertyFlags properties,
                                      const std::string& name) {
    auto memory = std::make_shared<DeviceMemory>();
    memory->bytes = bytes;
    try {
        memory->type = vk::findMemoryType(dev.physical, typeBits, properties);
    } catch (const ExecutorError&) {
        char bits[16];
        std::snprintf(bits, sizeof bits, "0x%x", typeBits);
        throw ExecutorError(name + ": none of the memory types " + bits + " has the properties it needs");
    }
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = bytes;
    mai.memoryTypeIndex = memory->type;
    VkDeviceMemory raw;
    if (const VkResult result = vkAllocateMemory(vkd, &mai, nullptr, &raw); result != VK_SUCCESS)
        throw ExecutorError(name + ": vkAllocateMemory of " + std::to_string(bytes) + " bytes in memory type " +
                            std::to_string(memory->type) + " failed: " + vk::resultName(result));
    memory->memory = owned::Memory(vkd, raw);
    memory->counted = &dev.allocatedBytes;
    memory->counted->fetch_add(bytes);
    if (dev.fn.setObjectName) {
        VkDebugUtilsObjectNameInfoEXT ni{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
        ni.objectType = VK_OBJECT_TYPE_DEVICE_MEMORY;
        ni.objectHandle = reinterpret_cast<uint64_t>(raw);
        ni.pObjectName = name.c_str();
        dev.fn.setObjectName(vkd, &ni);
    }
    return memory;
}

void Renderer::Impl::allocateHeaps(PlanState& s) {
    s.heaps.clear();
    const std::vector<MemoryHeap>& heaps = s.plan.memory().heaps;
    if (heaps.empty()) return;
    // Placed resources are transients (describeResources): a copy per frame slot, each in its
    // slot's heaps, or one copy in heaps that the frames share.
    const uint32_t copies = s.plan.memory().sharedAcrossFrames ? 1 : options.framesInFlight;
    s.heaps.resize(copies);
    for (uint32_t c = 0; c < copies; ++c)
        for (size_t h = 0; h < heaps.size(); ++h)
            s.heaps[c].push_back(allocate(std::max<VkDeviceSize>(heaps[h].bytes, 1), heaps[h].memoryTypeBits,
                                          VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                                          "heap " + std::to_string(h) + "#" + std::to_string(c)));
}

namespace {

/// Binds through `bind(memory, offset)`: into the resource's heap after checking `req` against
/// its placement, else into memory of its own.
template <typename Bind>
SharedMemory bindResource(RendererAccess::Impl& d, const PlanState& s, const ResourceState& r, uint32_t copy,
                          const VkMemoryRequirements& req, Bind bind) {
    const std::string name = r.desc->name + (r.perSlot ? "#" + std::to_string(copy) : "");
    if (r.placement == PlannedResource::kNoPlacement) {
        SharedMemory own = d.allocate(req.size, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, name);
        bind(own->memory.get(), 0);
        return own;
    }
    const MemoryLayout& layout = s.plan.memory();
    const MemoryPlacement& p = layout.placements[r.placement];
    const SharedMemory& heap = s.heaps.at(copy).at(p.heap);
    if (const std::string why = placementMismatch(req, p, layout.heaps[p.heap], heap->type); !why.empty()) {
        // forDevice recompiles a plan placed with another model, so with the device's
        // own the model and vkGet*MemoryRequirements disagree: a defect, not a user's error.
        const bool ownModel = layout.model == d.device.memoryModel()->name();
        throw ExecutorError("resource '" + r.desc->name + "' does not fit its place in heap " + std::to_string(p.heap) +
                            " at offset " + std::to_string(p.offset) + ": " + why + ". The plan was placed with the " +
                            "memory model '" + layout.model + "'" +
                            (ownModel ? ", the device's own, which answered differently from the resource created: "
                                        "a skygraph defect, please report it with this message"
                                      : "; run plans compiled with Device::memoryModel()"));
    }
    bind(heap->memory.get(), p.offset);
    return heap;
}

}  // namespace

SharedMemory Renderer::Impl::bindImage(const PlanState& s, const ResourceState& r, uint32_t copy, VkImage image) {
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(vkd, image, &req);
    return bindResource(*this, s, r, copy, req, [&](VkDeviceMemory memory, VkDeviceSize offset) {
        vk::check(vkBindImageMemory(vkd, image, memory, offset), "vkBindImageMemory");
    });
}

SharedMemory Renderer::Impl::bindBuffer(const PlanState& s, const ResourceState& r, uint32_t copy, VkBuffer buffer) {
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(vkd, buffer, &req);
    return bindResource(*this, s, r, copy, req, [&](VkDeviceMemory memory, VkDeviceSize offset) {
        vk::check(vkBindBufferMemory(vkd, buffer, memory, offset), "vkBindBufferMemory");
    });
}

RendererMemory RendererAccess::memory(const Renderer& renderer) {
    const Renderer::Impl& d = *renderer.impl_;
    const PlanState& s = *d.state;
    RendererMemory out;
    for (size_t c = 0; c < s.heaps.size(); ++c)
        for (size_t h = 0; h < s.heaps[c].size(); ++h)
            out.heaps.push_back({"heap " + std::to_string(h) + "#" + std::to_string(c), s.heaps[c][h]->memory.get(),
                                 s.heaps[c][h]->bytes});
    for (const ResourceState& r : s.resources) {
        const auto copyName = [&](size_t c) { return r.desc->name + (r.perSlot ? "#" + std::to_string(c) : ""); };
        const auto note = [&](size_t c, const SharedMemory& m, VkDeviceSize required) {
            if (!m) return;  // a present image
            if (r.placement == PlannedResource::kNoPlacement) {
                out.own.push_back({copyName(c), m->memory.get(), m->bytes});
                return;
            }
            out.placed.push_back({r.desc->name, uint32_t(c), m->memory.get(),
                                  s.plan.memory().placements[r.placement].offset, required});
        };
        for (size_t c = 0; c < r.images.size(); ++c) {
            if (!r.images[c].storage) continue;
            VkMemoryRequirements req;
            vkGetImageMemoryRequirements(d.vkd, r.images[c].image, &req);
            note(c, r.images[c].storage->memory, req.size);
        }
        for (size_t c = 0; c < r.buffers.size(); ++c) {
            VkMemoryRequirements req;
            vkGetBufferMemoryRequirements(d.vkd, r.buffers[c].buffer.get(), &req);
            note(c, r.buffers[c].memory, req.size);
        }
    }
    return out;
}

}  // namespace skygraph
