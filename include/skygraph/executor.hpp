// The executor: runs compiled plans on a Vulkan 1.3 device. It records exactly the plan's
// barriers and derives no synchronization of its own (contract §2).
#pragma once

#include <skygraph/compiler.hpp>
#include <skygraph/condition.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

class PassLibrary;  // skygraph/pass.hpp: pass implementations
class FrameData;    // skygraph/pass.hpp: per-frame values for pass implementations

/// Thrown for Vulkan failures and for plans or graphs the executor cannot run. The message
/// names the pass and resource involved where there is one.
class ExecutorError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct DeviceOptions {
    /// Physical device by index ("0") or case-insensitive name substring ("llvmpipe").
    /// Empty: a discrete GPU, else an integrated one, else any, else the CPU (lavapipe).
    std::string device;
    /// Khronos validation with synchronization validation (including QUEUE_SUBMIT checks).
    /// Also switched on by the environment variable SKYGRAPH_VALIDATION=1.
    bool validation = false;
    /// Log every validation message through spdlog as it arrives (they are always counted).
    bool logMessages = true;
};

/// One validation / debug-utils message that was counted.
struct ValidationMessage {
    VkDebugUtilsMessageSeverityFlagBitsEXT severity{};
    std::string idName;   ///< e.g. "SYNC-HAZARD-READ-AFTER-WRITE"
    std::string message;
};

/// Instance, physical device, logical device and one graphics+compute queue.
/// Owns every handle it creates; not copyable. Must outlive every Renderer made from it.
class Device {
public:
    /// Creates the instance and device. Throws ExecutorError when no device qualifies.
    static std::unique_ptr<Device> create(const DeviceOptions& options = {});
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    [[nodiscard]] VkInstance instance() const noexcept;
    [[nodiscard]] VkPhysicalDevice physicalDevice() const noexcept;
    [[nodiscard]] VkDevice device() const noexcept;
    [[nodiscard]] VkQueue queue() const noexcept;
    [[nodiscard]] uint32_t queueFamily() const noexcept;
    [[nodiscard]] const std::string& name() const noexcept;
    [[nodiscard]] bool validationEnabled() const noexcept;
    [[nodiscard]] float timestampPeriodNs() const noexcept;

    /// Number of warning and error messages received since creation or the last clear.
    [[nodiscard]] uint32_t messageCount() const;
    /// A copy of the counted messages (the first 256 are kept).
    [[nodiscard]] std::vector<ValidationMessage> messages() const;
    /// True if a counted message's id name or text contains `needle`.
    [[nodiscard]] bool hasMessage(std::string_view needle) const;
    void clearMessages();

    /// Lists "index: name (type)" for every physical device, for --device help.
    [[nodiscard]] static std::vector<std::string> listDevices();

    struct Impl;
    [[nodiscard]] Impl& impl() noexcept { return *impl_; }

private:
    explicit Device(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

/// Pixels of one image, converted to linear-agnostic float RGBA (values as stored; sRGB
/// bytes are returned as byte/255, BGRA swizzled to RGBA).
struct ImageData {
    uint32_t width = 0;
    uint32_t height = 0;
    VkFormat format = VK_FORMAT_UNDEFINED;
    std::vector<float> rgba;  ///< width*height*4

    [[nodiscard]] std::array<float, 4> pixel(uint32_t x, uint32_t y) const {
        const size_t i = (size_t(y) * width + x) * 4;
        return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
    }
};

/// Writes 8-bit RGBA PNG (values clamped to [0,1]). Throws ExecutorError on I/O failure.
void writePng(const std::filesystem::path& path, const ImageData& image);
/// Writes an HDR file by extension: Radiance .hdr or OpenEXR .exr (half float). Throws
/// ExecutorError on I/O failure.
void writeHdr(const std::filesystem::path& path, const ImageData& image);

/// An image that one renderer wrote and another renderer on the same Device reads, e.g. the
/// environment cube and IBL products that graphs/ibl.json builds when the environment changes
/// and graphs/raster.json samples every frame. A handle: copies share ownership of the Vulkan
/// image, which lives while any SharedImage or renderer holds it (so it may outlive the
/// renderer that made it). Get one from Renderer::shareImage(), hand it to
/// Renderer::importImage().
class SharedImage {
public:
    SharedImage();
    ~SharedImage();
    SharedImage(const SharedImage&);
    SharedImage& operator=(const SharedImage&);

    /// "graph 'ibl', resource 'environment'": where it came from, for messages.
    [[nodiscard]] const std::string& origin() const noexcept;

    struct Impl;

private:
    friend class Renderer;
    std::shared_ptr<const Impl> impl_;
};

struct RendererOptions {
    uint32_t width = 16;
    uint32_t height = 16;
    uint32_t framesInFlight = 2;
    /// Resource read back after every frame. Empty: the resource whose graph `final` is
    /// Present (the swapchain target). It must end the frame in TRANSFER_SRC_OPTIMAL, i.e.
    /// compile with CompileOptions::presentReplacement = ExternalState::TransferSrc.
    std::string readback;
    /// Directory with the GLSL includes (shaders/); empty: the source tree's shaders/.
    std::filesystem::path shaderDir;
    /// Recording code by pass type; borrowed, must outlive the renderer. Pass types without a
    /// factory (and Generic) run as Generic: they perform exactly their declared accesses.
    const PassLibrary* passes = nullptr;
};

/// GPU time of one pass in the last completed frame of a slot.
struct PassTiming {
    std::string pass;
    double milliseconds = 0.0;
};

/// Runs one plan of one graph. Owns all images, buffers, pipelines and command buffers it
/// creates; borrows `device` (which must outlive it). Not copyable.
class Renderer {
public:
    /// Creates resources, pipelines and per-frame state. Throws ExecutorError (e.g. a pass
    /// type without recording code, a format the device cannot use as the plan requires).
    Renderer(Device& device, const GraphDesc& graph, Plan plan, RendererOptions options = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Waits for the frame slot to be free, records the plan and submits. Non-blocking
    /// otherwise: up to framesInFlight frames run at once.
    void renderFrame();
    /// Waits until every submitted frame has finished.
    void waitIdle();
    /// Waits for the most recent frame and returns its read-back target.
    [[nodiscard]] ImageData readback();
    /// Waits for every submitted frame, then copies every mip and layer of the image
    /// `resource` to the host (element mip * layers + layer), e.g. an environment cube and
    /// its mip chain. The image is left in its end-of-frame layout (the plan's final layout).
    /// Throws ExecutorError for an unknown name, a buffer, or an image no frame has written.
    [[nodiscard]] std::vector<ImageData> readImage(const std::string& resource);
    /// Re-creates every output-sized resource for a new output extent.
    void resize(uint32_t width, uint32_t height);
    /// Replaces graph and plan (e.g. after a hot reload). On failure throws and keeps the old
    /// ones running.
    void setPlan(const GraphDesc& graph, Plan plan);
    /// Drops every cached shader and rebuilds the pipelines from the shader directory (after
    /// an edit). On failure throws ExecutorError with glslang's log; the old pipelines keep
    /// running.
    void reloadShaders();
    /// Imports a loaded texture: `pixels` (float RGBA, as stored) become the contents of mip 0
    /// (every layer) of the external image `resource`, now and whenever the plan is
    /// re-installed. Waits for the GPU. Throws ExecutorError for a wrong name, size or format.
    void setExternalImage(const std::string& resource, ImageData pixels);
    /// Shares the image of `resource`, an external image this plan exports (`final` set),
    /// with another renderer on the same Device. It holds this frame's contents once the
    /// frames that write it have finished (waitIdle()), in the layout of its `final` state.
    /// A later setPlan() or resize() makes new images; share again then. Throws
    /// ExecutorError for a resource that is not an exported image of the current plan.
    [[nodiscard]] SharedImage shareImage(const std::string& resource) const;
    /// Makes the external image `resource` use `image` instead of creating its own, now and
    /// whenever the plan is re-installed, and keeps a share of it. The graph must only read
    /// it, its format, extent, mips and layers must match, and it must arrive in the layout
    /// the producer leaves it in (`initial` here = `final` there). The caller orders the two
    /// renderers' work: the producer's frames must have finished (its waitIdle()) before
    /// this renderer's next frame. Throws ExecutorError on any mismatch, keeping the old plan.
    void importImage(const std::string& resource, SharedImage image);
    /// Values handed to pass implementations while recording (camera, exposure, ...).
    [[nodiscard]] FrameData& frameData() noexcept;
    /// The graph the current plan was compiled from.
    [[nodiscard]] const GraphDesc& graph() const noexcept;
    /// Per-pass GPU times of the most recently completed frame.
    [[nodiscard]] std::vector<PassTiming> lastTimings();

    [[nodiscard]] const Plan& plan() const noexcept;
    [[nodiscard]] uint64_t frameCount() const noexcept;

    /// Records the current plan for frame slot 0 into `cmd` (begun by the caller), without
    /// labels, timestamps or readback. For benchmarks that compare against hand recording.
    void recordInto(VkCommandBuffer cmd, uint32_t slot);

    struct Impl;

private:
    friend struct RendererAccess;  // benchmarks: the recorded handles, for hand recording
    std::unique_ptr<Impl> impl_;
};

/// Hot reload: watches a graph file and a shader directory and, on a change, recompiles and
/// hands the result to a Renderer. A failed rebuild logs the compiler's message as a warning
/// and leaves the last good plan and pipelines running. Borrows the renderer.
class HotReloader {
public:
    enum class Result : uint8_t { Unchanged, Reloaded, Failed };

    /// `registry` (borrowed; null: PassRegistry::withBuiltins()) parses the reloaded graph,
    /// e.g. `PassLibrary::registry()` when the renderer runs pass implementations.
    HotReloader(Renderer& renderer, std::filesystem::path graphFile, CompileOptions options,
                std::filesystem::path shaderDir = {}, const PassRegistry* registry = nullptr);

    /// Checks the watched files (by content) and reloads what changed. Cheap when nothing did.
    Result poll();
    /// The message of the last failed reload; empty after a success.
    [[nodiscard]] const std::string& lastError() const noexcept { return lastError_; }

private:
    Renderer& renderer_;
    std::filesystem::path graphFile_;
    CompileOptions options_;
    std::filesystem::path shaderDir_;
    const PassRegistry* registry_ = nullptr;
    size_t graphHash_ = 0;
    size_t shaderHash_ = 0;
    std::string lastError_;
};

}  // namespace skygraph
