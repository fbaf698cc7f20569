// The Vulkan device a Renderer runs on: instance, physical and logical device, its queues,
// and the validation messages counted while it lives. skygraph makes all of them itself
// (Device::create); a renderer cannot run on an instance or device of the application's own.
#pragma once

#include <skygraph/graph.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace skygraph {

class MemoryModel;  // skygraph/memory.hpp

/// Thrown for Vulkan failures and for plans or graphs the executor cannot run. The message
/// names the pass and resource involved where there is one.
class ExecutorError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// An ExecutorError thrown before anything is allocated, when the plan needs more than the
/// device can hold: a resource past one of its size limits (dimensions, layers, buffer ranges)
/// or one it reports no memory for, or all of them together past the memory a renderer allows
/// itself (half the largest device-local heap). Smaller sizes, or a larger device, would run.
class DeviceCapacityError : public ExecutorError {
public:
    /// `resource`: the graph resource past a limit; empty when no one resource is (all of
    /// them together over the memory cap, a heap of transients past the largest allocation).
    explicit DeviceCapacityError(const std::string& message, std::string resource = {})
        : ExecutorError(message), resource_(std::move(resource)) {}
    /// The resource past a limit, or empty (above). Valid while this exception object lives.
    [[nodiscard]] const std::string& resource() const noexcept { return resource_; }

private:
    std::string resource_;
};

/// An ExecutorError for a graph resource the device or the window cannot have as the graph
/// declares it and the plan uses it: a format the device cannot make with the plan's usages,
/// one the window's surface cannot present, or a presented image that the present images
/// cannot be (another format, a fixed extent of another size, several mips or layers, a usage
/// they were not created with). A change to the graph would run.
class UnsupportedResourceError : public ExecutorError {
public:
    /// `resource`: the graph resource refused.
    UnsupportedResourceError(const std::string& message, std::string resource)
        : ExecutorError(message), resource_(std::move(resource)) {}
    /// The resource refused. Valid while this exception object lives.
    [[nodiscard]] const std::string& resource() const noexcept { return resource_; }

private:
    std::string resource_;
};

/// What presenting to a window needs of the Device. Both halves come from the application's
/// window library (GLFW: glfwGetRequiredInstanceExtensions and glfwCreateWindowSurface); the
/// library itself depends on no window system.
struct PresentationOptions {
    /// Instance extensions the window system needs: VK_KHR_surface and the platform's (e.g.
    /// VK_KHR_xcb_surface). Each must be available, or Device::create throws naming it.
    std::vector<std::string> instanceExtensions;
    /// Makes the window's surface once the instance exists; called once, during
    /// Device::create. The Device owns what it returns and destroys it before the instance.
    /// Returning VK_NULL_HANDLE (or throwing) makes Device::create throw ExecutorError.
    std::function<VkSurfaceKHR(VkInstance)> createSurface;
};

struct DeviceOptions {
    /// Physical device by index ("0") or case-insensitive name substring ("llvmpipe").
    /// Empty: a discrete GPU, else an integrated one, else a virtual one, else the CPU
    /// (lavapipe), else a device of any other type.
    std::string device;
    /// Khronos validation with synchronization validation (including QUEUE_SUBMIT checks).
    /// Also switched on by the environment variable SKYGRAPH_VALIDATION=1. The layer takes
    /// the QUEUE_SUBMIT checks only from the environment, so Device::create sets
    /// VK_LAYER_ENABLES while it creates the instance and device, then puts back what was there: no
    /// other thread should read or change the environment meanwhile.
    bool validation = false;
    /// Log every validation message through spdlog as it arrives (they are always counted).
    bool logMessages = true;
    /// Set to present to a window: the instance gets these extensions, the surface is made
    /// with it, and only a device with a graphics+compute queue that presents to that surface
    /// qualifies (VK_KHR_swapchain is then enabled). Empty: headless, no surface, no
    /// VK_KHR_swapchain.
    std::optional<PresentationOptions> presentation;
    /// Give the compute and transfer queue kinds queues of their own where the device has
    /// them: a compute family without graphics (else a second graphics queue), a transfer
    /// family without compute (else the compute queue). False, or the environment variable
    /// SKYGRAPH_SEPARATE_QUEUES=0: every kind submits to the graphics queue.
    bool separateQueues = true;
    /// The application's name and version in VkApplicationInfo, which drivers key their
    /// per-application settings on; the engine is named "skygraph".
    std::string applicationName = "skygraph";
    uint32_t applicationVersion = 0;
    /// Device extensions the application's own Vulkan work on this device needs, enabled
    /// beside skygraph's. A device that lacks one is unsuitable (Device::create lists it
    /// with the extension it lacks); their features, where they have any, are not enabled.
    std::vector<std::string> deviceExtensions;
};

/// One validation / debug-utils message that was counted. A plain value; copies own their text.
struct ValidationMessage {
    VkDebugUtilsMessageSeverityFlagBitsEXT severity{};
    std::string idName;   ///< e.g. "SYNC-HAZARD-READ-AFTER-WRITE"
    std::string message;
};

/// Instance, physical device, logical device, a graphics+compute queue (which also presents,
/// when DeviceOptions::presentation is set) and the compute and transfer queues, and the
/// surface then. Device::create() makes every one of them: there is no way to hand skygraph a
/// VkInstance, VkDevice or queue of the application's own, so an engine that renders with
/// skygraph does its own Vulkan work on this device (device(), queue()), or keeps a device of
/// its own apart. Owns every handle it creates and destroys them with itself; not copyable or
/// movable (what is made from it keeps a reference). Must outlive everything made from it,
/// since each destroys its Vulkan objects with this device: every Renderer, Swapchain and
/// StagingBuffer, every SharedImage (which may outlive its renderer), and whatever the
/// application creates with device() (e.g. vk_handles.hpp owners, pipeline_builder.hpp
/// pipelines).
/// Threads: the device and every Renderer, Swapchain and HotReloader made with it are used
/// by one thread at a time, all of them together, not each on its own: they submit to its
/// queues, which Vulkan lets one thread use at a time, and the application's own submits to
/// those queues must not overlap their calls either. Validation messages may arrive on any
/// thread, and the message accessors, memoryModel(), allocatedBytes() and
/// StagingBuffer::create() are safe from any thread.
class Device {
public:
    /// Creates the instance and device (and the surface, when presenting); the caller owns the
    /// result. Throws ExecutorError when no device qualifies, naming the devices there are and
    /// why each does not (e.g. "cannot present to the surface"), or when validation is asked
    /// for and the Khronos validation layer is not installed.
    static std::unique_ptr<Device> create(const DeviceOptions& options = {});
    /// As finish(), except that a Renderer, Swapchain, SharedImage or StagingBuffer of this
    /// device still alive ends the process (std::abort) with a message naming them.
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    /// The handles are owned by this Device and valid while it lives; do not destroy them.
    [[nodiscard]] VkInstance instance() const noexcept;
    [[nodiscard]] VkPhysicalDevice physicalDevice() const noexcept;
    [[nodiscard]] VkDevice device() const noexcept;
    /// The surface made by DeviceOptions::presentation, owned by this Device and valid while it
    /// lives; VK_NULL_HANDLE when headless.
    [[nodiscard]] VkSurfaceKHR surface() const noexcept;
    /// The graphics queue (graphics and compute, and present when there is a surface): every
    /// single-queue plan, setup work and presentation are submitted to it. Owned by the
    /// device and valid while this Device lives; the class comment says when the application
    /// may submit to it.
    [[nodiscard]] VkQueue queue() const noexcept;
    [[nodiscard]] uint32_t queueFamily() const noexcept;
    /// The queue a plan's submits of `kind` go to: one of its own, or the graphics queue where
    /// the device has none to spare or DeviceOptions::separateQueues is off. Kinds that share
    /// one queue run there in submission order, with the plan's semaphores. Valid while this
    /// Device lives, as queue().
    [[nodiscard]] VkQueue queue(QueueKind kind) const noexcept;
    /// The queue family of each queue kind (indexed by QueueKind), for
    /// CompileOptions::queueFamilies: kinds of different families move exclusive resources
    /// with the plan's ownership transfers.
    [[nodiscard]] std::array<uint32_t, kQueueKinds> queueFamilies() const noexcept;
    /// The physical device's name; the reference is valid while this Device lives.
    [[nodiscard]] const std::string& name() const noexcept;
    [[nodiscard]] bool validationEnabled() const noexcept;
    /// Nanoseconds per timestamp tick.
    [[nodiscard]] float timestampPeriodNs() const noexcept;
    /// How much memory this device needs for each resource, for CompileOptions::memory: it
    /// asks the device (vkGetDeviceImageMemoryRequirements, creating nothing) about exactly the
    /// image or buffer a Renderer creates, keeps the DEVICE_LOCAL memory types, and its name()
    /// is name(). A Renderer runs only plans compiled with it (it recompiles others). Shared:
    /// the same model every call; safe to use from any thread. It may outlive this Device,
    /// but once the device is destroyed (finish() or the destructor) its requirements() and
    /// bufferImageGranularity() throw ExecutorError.
    [[nodiscard]] std::shared_ptr<const MemoryModel> memoryModel() const noexcept;
    /// Bytes of device memory that renderers on this device hold now for their plans: every
    /// vkAllocateMemory a Renderer makes (the plan's images and buffers, its heaps, staging)
    /// not yet freed, whatever its memory type. Memory that pass implementations allocate on
    /// their own (a model's geometry and textures, the path tracer's scene) or others do (an
    /// ImGui backend) is not counted. Safe from any thread.
    [[nodiscard]] uint64_t allocatedBytes() const noexcept;

    /// Number of warning and error messages received since creation or the last clear,
    /// performance warnings left out.
    [[nodiscard]] uint32_t messageCount() const;
    /// A copy of the counted messages (the first 256 are kept), owned by the caller.
    [[nodiscard]] std::vector<ValidationMessage> messages() const;
    /// True if a counted message's id name or text contains `needle`.
    [[nodiscard]] bool hasMessage(std::string_view needle) const;
    /// Number of performance warnings (messages of type PERFORMANCE only, such as a layout
    /// that is valid but not the optimal one) since creation or the last clear.
    [[nodiscard]] uint32_t performanceWarningCount() const;
    /// A copy of those warnings (the first 256 are kept), owned by the caller.
    [[nodiscard]] std::vector<ValidationMessage> performanceWarnings() const;
    /// Forgets the counted messages and performance warnings: both counts are 0 again.
    void clearMessages();

    /// Waits for the queue, then destroys the logical device and the surface while validation
    /// still listens: the layer reports each object made from the device that is still alive
    /// (a leaked handle), and messageCount() counts those reports. Every Renderer, Swapchain,
    /// SharedImage and StagingBuffer of this device must be destroyed first: while one lives,
    /// throws ExecutorError naming them and destroys nothing. Afterwards device() and
    /// surface() are VK_NULL_HANDLE, making any of those from it throws ExecutorError, and only
    /// name(), validationEnabled() and the message accessors may be used. The destructor does
    /// the same when this was not called; calling it twice does nothing more.
    void finish();

    /// Lists "index: name (type)" for every physical device, for --device help. Makes and
    /// destroys an instance of its own; needs no Device. Empty when Vulkan cannot start.
    [[nodiscard]] static std::vector<std::string> listDevices();

private:
    struct Impl;
    friend struct DeviceAccess;  // the implementation's own access; not part of the API
    explicit Device(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace skygraph
