// Private to the executor: the state a Renderer keeps for one plan (resources, passes, frame
// slots) and Renderer::Impl, whose members are defined by concept in
//   renderer.cpp            the public Renderer API, building a plan, read-back, hand frames
//   renderer_resources.cpp  images, buffers, views, per-slot copies, importing externals
//   renderer_memory.cpp     device memory: resources' own, and the heaps transients are placed in
//   renderer_passes.cpp     each pass's recording code, render pass, framebuffers, barriers
//   renderer_frame.cpp      frame slots, submission, timestamps
//   renderer_setup.cpp      the setup plan before the first frame, and reading images back
//   renderer_present.cpp    frames into presentable images: a Swapchain's or the application's
//   frame_recording.cpp     recording a plan's steps into a CommandSink (no device needed)
#pragma once

#include "barrier_batch.hpp"
#include "command_sink.hpp"
#include "device_access.hpp"
#include "device_memory.hpp"
#include "pass_error.hpp"
#include "spirv_cache.hpp"
#include "swapchain.hpp"
#include "texel_encoding.hpp"
#include "vk_util.hpp"

#include <skygraph/renderer.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/swapchain.hpp>
#include <skygraph/pipeline_builder.hpp>
#include <skygraph/shader_compiler.hpp>

#include <algorithm>
#include <functional>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

// The .cpp files above use `using namespace detail;` for these names.
namespace skygraph::detail {

inline constexpr uint64_t kWaitForever = std::numeric_limits<uint64_t>::max();

inline VkImageAspectFlags aspectOf(const FormatInfo& f) {
    if (!f.isDepthStencil()) return VK_IMAGE_ASPECT_COLOR_BIT;
    VkImageAspectFlags a = 0;
    if (f.hasDepth) a |= VK_IMAGE_ASPECT_DEPTH_BIT;
    if (f.hasStencil) a |= VK_IMAGE_ASPECT_STENCIL_BIT;
    return a;
}

/// A buffer and the memory it is bound to (its own, or a heap it shares with other
/// transients); mapped when host-visible. Declared before the buffer, the memory is released
/// after it.
struct OwnedBuffer {
    SharedMemory memory;
    owned::Buffer buffer;
    void* mapped = nullptr;
    VkDeviceSize size = 0;
};

/// A Vulkan image and the memory it is bound to (its own, or a heap it shares with other
/// transients). Shared so that another renderer on the same device can sample it
/// (Renderer::importImage): it lives while any renderer or SharedImage holds it. Declared
/// before the image, the memory is released after it.
struct ImageStorage {
    SharedMemory memory;
    owned::Image image;
    bool concurrent = false;  ///< Created VK_SHARING_MODE_CONCURRENT over the device's families.
};

struct ImageCopy {
    std::shared_ptr<const ImageStorage> storage;
    VkImage image = VK_NULL_HANDLE;  ///< storage's image
    std::map<std::tuple<int, uint32_t, uint32_t, uint32_t, uint32_t>, owned::ImageView> views;
};

/// One plan resource: its description and one or N (per frame slot) Vulkan copies, or, for the
/// Present resource of a presenting renderer, the present images.
///
/// Per-slot state (PassSlot, the final barriers) is kept per *binding slot*: frame slot f with
/// present image i is binding slot f * presentImages + i. Headless there is one present image
/// and the binding slot is the frame slot.
struct ResourceState {
    const ResourceDesc* desc = nullptr;
    bool isImage = false;
    bool perSlot = false;  ///< The plan's PlannedResource::copies, with more than one slot.
    bool presented = false;  ///< The present images (PresentImages), not images of our own.
    uint32_t presentImages = 1;  ///< PlanState::presentImages.
    /// An UploadPass of the plan writes it: Renderer::stageUpload() has somewhere to copy to.
    bool uploaded = false;
    /// BoundResource::contentsReplaced points here: each setup step for it and each import
    /// counts one.
    uint64_t contentsReplaced = 0;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkImageAspectFlags aspect = 0;
    uint32_t width = 1, height = 1, mips = 1, layers = 1;
    VkDeviceSize size = 0;
    VkImageUsageFlags imageUsage = kAlwaysUsable.image;
    VkBufferUsageFlags bufferUsage = kAlwaysUsable.buffer;
    /// Index into Plan::memory().placements, or PlannedResource::kNoPlacement: a transient
    /// bound into its frame slot's heap rather than memory of its own.
    uint32_t placement = PlannedResource::kNoPlacement;
    std::vector<ImageCopy> images;
    std::vector<OwnedBuffer> buffers;

    /// The copy that binding slot `slot` uses.
    [[nodiscard]] uint32_t copyFor(uint32_t slot) const {
        return presented ? slot % presentImages : perSlot ? slot / presentImages : 0;
    }
    /// What a barrier on this resource names in binding slot `slot`.
    [[nodiscard]] BarrierTarget barrierTarget(uint32_t slot) const {
        const uint32_t c = copyFor(slot);
        if (isImage) return {images.at(c).image, VK_NULL_HANDLE, aspect};
        return {VK_NULL_HANDLE, buffers.at(c).buffer.get(), 0};
    }
    [[nodiscard]] uint32_t mipWidth(uint32_t mip) const { return std::max(1u, width >> mip); }
    [[nodiscard]] uint32_t mipHeight(uint32_t mip) const { return std::max(1u, height >> mip); }
};

/// Per pass and frame slot: everything recording needs, with handles resolved.
struct PassSlot {
    owned::Framebuffer framebuffer;  ///< Graphics passes.
    VkExtent2D extent{1, 1};      ///< The framebuffer's.
    BarrierBatch before;  ///< The plan's batch before the pass.
    BarrierBatch inPass;  ///< The plan's in-pass barriers: between its copies out and in.
    std::vector<BoundResource> bound;  ///< What the pass's recording code sees: parallel to its usages.
};

/// The attachments of a pass, from its usages: a pass with any is a graphics pass, recorded
/// inside a render pass of them.
struct PassAttachments {
    std::vector<uint32_t> colors;  ///< Usage indices of ColorAttachment usages, in order.
    int32_t depth = -1;            ///< Usage index of the DepthAttachment usage, or -1.
    uint32_t layers = 1;           ///< The framebuffer's: the most layers of any attachment.
    [[nodiscard]] bool any() const noexcept { return !colors.empty() || depth >= 0; }
};

/// `pass`'s attachments. Throws ExecutorError for a second depth attachment.
[[nodiscard]] PassAttachments attachmentsOf(const PlannedPass& pass, const std::vector<ResourceState>& resources);
/// Throws ExecutorError naming the pass unless its usages fill `type`'s slots as the type
/// declares them: each usage one declared slot, with the slot's usage; required slots filled;
/// a slot that is not repeated filled once.
void checkSlots(const PlannedPass& pass, const PassTypeInfo& type, const std::vector<ResourceState>& resources);
/// For a type that takes any usage: throws ExecutorError naming the pass and the resource for
/// a usage that names a slot.
void checkNoSlots(const PlannedPass& pass, const PassTypeInfo& type, const std::vector<ResourceState>& resources);
/// Throws ExecutorError, naming the pass, for what its type's own validators refuse of
/// `desc` (its params, its usages: the loader runs them for a graph file, not for a
/// GraphDesc built in code) and of `pass` as `plan` runs it.
void checkWithTypeValidators(const PlannedPass& pass, const PassDesc& desc, const PassTypeInfo& type,
                             const GraphDesc& graph, const Plan& plan);
/// The framebuffer's extent: the attachments' (their usages' base mip). Throws ExecutorError
/// naming the pass and two of them when they differ.
[[nodiscard]] VkExtent2D framebufferExtent(const PlannedPass& pass, const PassAttachments& attachments,
                                           const std::vector<ResourceState>& resources);

/// What the executor does for a plan step: a pass's recording, or a step the compiler inserted.
enum class StepKind : uint8_t { Pass, Clear, Readback, Upload, Clobber };

struct PassState {
    const PlannedPass* pass = nullptr;
    const PassDesc* desc = nullptr;
    std::string label;  ///< The pass's name, NUL-terminated for debug labels (the plan's is a view).
    StepKind kind = StepKind::Pass;
    /// Steps of kind Pass: the recording code from the PassLibrary (the library's Generic
    /// for a type without its own).
    std::unique_ptr<PassImplementation> implementation;
    PassAttachments attachments;
    owned::RenderPass renderPass;  ///< Graphics passes.
    std::vector<VkClearValue> clearValues;
    std::vector<PassSlot> slots;
};

/// Whether Renderer::readback() and readImage() convert `format` to floats (renderer.cpp
/// reads each such format); checked when a plan with read-backs is installed, before
/// anything renders.
[[nodiscard]] bool readsBack(VkFormat format) noexcept;
/// The ExecutorError message for reading back `resource` of an unconverted `format`.
[[nodiscard]] std::string notReadBackable(const std::string& resource, VkFormat format);

/// Host memory that a Readback step of the frame copies its image into, one per frame slot
/// (not per binding slot).
struct ReadbackTarget {
    uint32_t step = 0;      ///< Index into Plan::passes().
    uint32_t resource = 0;  ///< Index into Plan::resources().
    std::vector<OwnedBuffer> perSlot;
};

/// Everything that belongs to one plan; replaced whole by setGraph and resize.
struct PlanState {
    explicit PlanState(CompiledGraph c) : compiled(std::move(c)), graph(compiled.graph()), plan(compiled.plan()) {}
    PlanState(const PlanState&) = delete;
    PlanState& operator=(const PlanState&) = delete;

    CompiledGraph compiled;
    const GraphDesc& graph;  ///< compiled's
    const Plan& plan;        ///< compiled's
    [[nodiscard]] uint32_t outputWidth() const noexcept { return compiled.outputWidth(); }
    [[nodiscard]] uint32_t outputHeight() const noexcept { return compiled.outputHeight(); }
    std::vector<ResourceState> resources;  ///< Parallel to plan.resources().
    std::vector<PassState> passes;         ///< Parallel to plan.passes().
    std::vector<BarrierBatch> finals;      ///< Per slot.
    /// Each submit's releases (Submit::releases) per slot: releases[slot][submit].
    std::vector<std::vector<BarrierBatch>> releases;
    /// The queue family of each queue kind that the plan was compiled for.
    [[nodiscard]] const std::array<uint32_t, kQueueKinds>& families() const noexcept {
        return compiled.options().queueFamilies;
    }
    std::vector<ReadbackTarget> readbacks; ///< One per Readback step of the plan.
    /// The plan's heaps (Plan::memory().heaps), one allocation each per frame slot, or one
    /// when the frames share them (MemoryLayout::sharedAcrossFrames): heaps[copy][heap]. The
    /// placed resources' copy c is bound into heaps[c] (their one copy into heaps[0] when shared).
    std::vector<std::vector<SharedMemory>> heaps;
    Plan setup;  ///< planSetup of `plan`: what ran before the first frame.
    /// Presenting: the plan's Present resource (index into plan.resources()) and the number of
    /// present images; headless: -1 and 1.
    int32_t presentResource = -1;
    uint32_t presentImages = 1;
    /// Headless, the resource of a plan compiled to present (left in PRESENT_SRC_KHR, which a
    /// headless frame cannot leave its own image in); else -1.
    int32_t presentsWithoutImages = -1;

    [[nodiscard]] const ReadbackTarget* readbackOf(uint32_t resource) const {
        for (const ReadbackTarget& t : readbacks)
            if (t.resource == resource) return &t;
        return nullptr;
    }
};

/// What recording one frame needs besides the plan's state.
/// Renderer::stageUpload's pixels, by resource name.
using StagedUploads = std::map<std::string, std::shared_ptr<const StagingBuffer>, std::less<>>;

struct FrameRecording {
    uint32_t slot = 0;  ///< The binding slot.
    uint64_t frameIndex = 0;
    VkSampler linearSampler = VK_NULL_HANDLE;
    VkSampler repeatSampler = VK_NULL_HANDLE;
    const FrameData* frameData = nullptr;
    const StagedUploads* staged = nullptr;  ///< What UploadPasses copy (RecordContext::staged).
    VkQueryPool queries = VK_NULL_HANDLE;  ///< Two timestamps per pass; none when null.
    uint32_t queryCount = 0;
    /// Per queue kind: whether its passes write timestamps (their queue family has valid bits).
    std::array<bool, kQueueKinds> timestamps{true, true, true};
    /// The first submit resets the queries; false when the host reset them (vkResetQueryPool).
    bool resetQueries = true;
    bool labels = false;  ///< A debug label around each pass.
    /// Test-only: changes the plans that fill passes' sampled images before they are recorded.
    const std::function<void(Plan&)>* sampledImagePlanEdit = nullptr;
};

/// The usage flags that planned usage `u` needs of its resource, added to `image` / `buffer`.
void addUsageFlags(const PlannedUsage& u, bool isImage, VkImageUsageFlags& image, VkBufferUsageFlags& buffer) noexcept;
/// The image usage a layout the resource arrives in or is left in needs.
[[nodiscard]] VkImageUsageFlags layoutUsage(VkImageLayout layout) noexcept;
/// Every image usage plan resource `resource` needs: its usages' (transfers included), its
/// initial and final layouts'.
[[nodiscard]] VkImageUsageFlags planImageUsage(const Plan& plan, uint32_t resource);

/// Records submit `submit` of binding slot `r.slot` of `s` into `sink`: each of its passes'
/// barrier batch and work (inserted clears and read-backs included), its releases, and in the
/// last submit the final barriers. The first submit resets the timestamp queries unless the
/// host did.
void recordSubmit(CommandSink& sink, PlanState& s, const FrameRecording& r, size_t submit);
/// Every submit of binding slot `r.slot`, in submission order, into one sink (for a command
/// log, and for a plan of one submit).
void recordFrame(CommandSink& sink, PlanState& s, const FrameRecording& r);

/// A Downsample step's blit: the whole of level `from` onto the whole of level `to`, of an
/// image whose mip 0 is `width` x `height`.
[[nodiscard]] VkImageBlit downsampleRegion(VkImageAspectFlags aspect, uint32_t width, uint32_t height,
                                           const SubresourceRange& from, const SubresourceRange& to);
/// Records the compiler's plan that fills `fills` (RecordContext::fillSampledImages).
/// `edit`, when given and not empty, changes the plan first (a negative control).
void recordSampledImageFills(CommandSink& sink, std::span<const SampledImageFill> fills,
                             const std::array<uint32_t, kQueueKinds>& families,
                             const std::function<void(Plan&)>* edit = nullptr);

/// What the executor does for plan step `pass`.
[[nodiscard]] StepKind stepKindOf(const PlannedPass& pass);
/// The plan's barriers of pass `ps` (before it, and in it) for binding slot `slot`, in Vulkan's
/// form, naming the slot's copies of `s`'s resources.
void translatePassBarriers(const PlanState& s, PassState& ps, uint32_t slot);
/// The plan's final barriers, per binding slot (`slots` of them).
void translateFinalBarriers(PlanState& s, uint32_t slots);

/// What a swapped import leaves behind for the frames already submitted: the old image (and
/// its views), and the framebuffers and recording code of the passes that used it.
struct RetiredImport {
    ImageCopy image;
    std::vector<owned::Framebuffer> framebuffers;
    std::vector<std::unique_ptr<PassImplementation>> implementations;
    uint64_t untilFrame = 0;  ///< Frames submitted before this one may still use them.
};

struct FrameSlot {
    /// Per queue kind (indexed by QueueKind): a pool of its queue's family, and a command buffer
    /// per submit of the plan on that queue, allocated as needed.
    std::array<owned::CommandPool, kQueueKinds> pools;
    std::array<std::vector<VkCommandBuffer>, kQueueKinds> cmds;
    /// Under validation: a binary semaphore per semaphore wait of the frame (renderer_frame.cpp).
    std::vector<owned::Semaphore> binaries;
    /// The semaphore the slot's frames acquire swapchain images with, made on first use. The
    /// renderer's, not the swapchain's: the slot's fence says when its last wait has run, and
    /// another renderer presenting to the same swapchain knows nothing of that fence.
    owned::Semaphore acquire;
    owned::Fence fence;
    uint64_t frame = 0;  ///< frameIndex of the frame last submitted in this slot.
    std::shared_ptr<void> setupKeep;  ///< A pending setup's staging, until this slot's frame finishes.
    StagedUploads stagedKeep;  ///< What the frame's UploadPasses copy, until they have.
    /// A background frame (Renderer::renderFrameInBackground): a fence per vkQueueSubmit2
    /// before its last submit, and that submit, held back until those fences signal.
    std::vector<owned::Fence> runFences;
    struct HeldSubmit {
        VkCommandBufferSubmitInfo cmd{};
        std::vector<VkSemaphoreSubmitInfo> waits, signals;
        VkQueue queue = VK_NULL_HANDLE;
        bool recordsPasses = false;
    };
    std::optional<HeldSubmit> held;
    owned::QueryPool queries;
    uint32_t queryCount = 0;
    bool submitted = false;
    bool timingsPending = false;
    std::vector<std::string> passNames;  ///< Of the frame last recorded in this slot.
};

}  // namespace skygraph::detail

namespace skygraph {

struct SharedImage::Impl {
    explicit Impl(DeviceAccess::Impl& owner) : use(owner, DeviceUser::SharedImage) {}
    detail::DeviceUse use;
    std::shared_ptr<const detail::ImageStorage> storage;
    VkDevice device = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0, height = 0, mips = 0, layers = 0;
    VkImageUsageFlags usage = 0;
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;  ///< The producer's final layout.
    std::string origin;
};

struct Renderer::Impl {
    detail::DeviceUse use;
    Device& device;
    DeviceAccess::Impl& dev;
    VkDevice vkd;
    RendererOptions options;
    /// Keeps the shader sources the running pipelines were built from (ShaderCompiler::source),
    /// for rebuilds other than a reload of the shaders. Shared with the renderers made from this
    /// one (RendererOptions::shaderCompiler) until one of them reads the shaders
    /// again.
    std::shared_ptr<ShaderCompiler> shaders;
    owned::Sampler linearSampler;  ///< For pass implementations: trilinear, clamp.
    owned::Sampler repeatSampler;  ///< Trilinear, repeat U, clamp V (equirect).
    FrameData frameData;
    detail::StagedUploads staged;  ///< For the next frame (Renderer::stageUpload).
    /// Pixels given to setExternalImage, by resource name; uploaded on every import.
    std::map<std::string, ImageData> uploads;
    /// Images of other renderers that externals use instead of their own (importImage).
    std::map<std::string, SharedImage> imports;
    std::unique_ptr<detail::PlanState> state;
    std::vector<detail::FrameSlot> frames;
    uint64_t frameIndex = 0;
    int64_t lastSlot = -1;
    uint32_t lastBinding = 0;  ///< The binding slot of the last frame (lastSlot's, headless).
    std::vector<PassTiming> timings;
    std::optional<uint64_t> timingsFrame;  ///< The frame `timings` are of (FrameSlot::frame).

    /// Presenting: the images the plan's Present resource is, and where they came from.
    struct PresentBinding {
        PresentImages images;
        const SwapchainAccess::Impl* swapchain = nullptr;  ///< Null: the application's own images.
        uint64_t imagesId = 0;                       ///< The swapchain's images_id, when bound.
        std::weak_ptr<const bool> swapchainLifetime;  ///< Its Impl::lifetime, when bound.
        /// The plan presents another format or usage than `images` have (setGraph): the state
        /// renders into a stand-in until the next frame re-creates the swapchain and binds its
        /// new images. The renderer still presents, at `images`' extent.
        bool awaitingImages = false;
    };
    std::optional<PresentBinding> present;
    /// Test hooks (RendererAccess): stages in place of the plan's acquire wait (0: no wait) and
    /// of presentSignalStages.
    std::optional<VkPipelineStageFlags2> acquireWaitOverride;
    std::function<void(Plan&)> setupPlanEdit;  ///< RendererAccess::editSetupPlans
    /// Pass types that ran as Generic and were warned of: once per renderer, not per rebuild.
    mutable std::set<std::string, std::less<>> typesRunAsGeneric;
    std::function<void(Plan&)> sampledImagePlanEdit;  ///< RendererAccess::editSampledImagePlans
    std::optional<VkPipelineStageFlags2> signalOverride;

    Impl(Device& d, RendererOptions o)
        : use(DeviceAccess::impl(d), DeviceUser::Renderer), device(d), dev(DeviceAccess::impl(d)), vkd(d.device()), options(std::move(o)),
          shaders(options.shaderCompiler ? options.shaderCompiler
                                         : std::make_shared<ShaderCompiler>(
                                               options.shaderDir,
                                               options.shaderCacheDir.value_or(ShaderCompiler::defaultCacheDir()))) {
        options.shaderCompiler.reset();  // held by `shaders` alone: a reload lets the old sources go
    }

    // --- renderer.cpp: building a plan --------------------------------------------------------
    std::unique_ptr<detail::PlanState> build(CompiledGraph compiled);
    /// Makes `next`, just built, the plan state, once this renderer's frames have finished
    /// (the caller has waited for them).
    void replaceState(std::unique_ptr<detail::PlanState> next);

    // --- renderer_memory.cpp: device memory -------------------------------------------------
    /// A memory object of `bytes` from a type among `typeBits` with `properties`, named `name`
    /// for debug utils. Throws ExecutorError when there is no such type or allocation fails.
    [[nodiscard]] detail::SharedMemory allocate(VkDeviceSize bytes, uint32_t typeBits,
                                                VkMemoryPropertyFlags properties, const std::string& name);
    /// Allocates the plan's heaps (s.heaps) for every frame slot, or once when the frames share
    /// them, DEVICE_LOCAL, named "heap h#c".
    void allocateHeaps(detail::PlanState& s);
    /// Binds `image` (or `buffer`), copy `copy` of resource `r`: into its heap at its
    /// placement's offset after checking that the device's requirements fit the placement,
    /// else into memory of its own. Returns the memory it is bound to. Throws ExecutorError
    /// naming the resource when the placement does not fit (a plan compiled with another
    /// memory model).
    detail::SharedMemory bindImage(const detail::PlanState& s, const detail::ResourceState& r, uint32_t copy, VkImage image);
    detail::SharedMemory bindBuffer(const detail::PlanState& s, const detail::ResourceState& r, uint32_t copy, VkBuffer buffer);
    /// `compiled` as the renderer runs it: compiled with this device's memory model and queue
    /// families (and at `extent` when given), compiled again with them when it was not
    /// (Renderer::compiled() then reports the recompiled one). Never asks the model it was
    /// compiled with, which may be another device's, and gone.
    [[nodiscard]] CompiledGraph forDevice(CompiledGraph compiled, std::optional<VkExtent2D> extent = {}) const;

    // --- renderer_resources.cpp: resources and their per-slot copies --------------------------
    /// Per-frame copies of the plan's read-backs: host-visible buffers.
    void createReadbackTargets(detail::PlanState& s);
    /// A host-visible, coherent buffer of its own memory, mapped (staging and read-backs).
    detail::OwnedBuffer makeHostBuffer(VkDeviceSize size, VkBufferUsageFlags usage);
    VkImageView view(detail::ResourceState& r, uint32_t copy, VkImageViewType type,
                     const SubresourceRange& range, bool attachment);
    void describeResources(detail::PlanState& s);
    void createResources(detail::PlanState& s);
    /// Throws ExecutorError unless `image` is of this device and of the format, extent, mips
    /// and layers that `d` declares at that output extent: what an import must match whether
    /// or not the plan uses the resource.
    void checkImportShape(const ResourceDesc& d, uint32_t outputWidth, uint32_t outputHeight,
                          const SharedImage& image) const;
    /// The single copy of imported resource `r`, after checking that it fits the plan.
    detail::ImageCopy adoptImport(const detail::PlanState& s, size_t index, const SharedImage& image) const;
    void buildSized(detail::PlanState& s);

    // --- renderer_setup.cpp: plans around the frame -------------------------------------------
    /// Runs the plan's setup (planSetup): every external resource gets defined contents (the
    /// uploaded pixels, its clear value, or grey) and the state the frame expects it in. Runs
    /// outside any frame and waits.
    /// `only`: that external resource alone (updateExternalImage); the others keep theirs.
    /// `withNextFrame`: when every resource it sets up has one copy and the plan submits all
    /// its work to Device::queue(), the steps are recorded at the start of the next frame's
    /// first submit instead (pendingSetups), and nothing waits; otherwise it waits for this
    /// renderer's frames first (without it, the caller has waited).
    void runSetup(detail::PlanState& s, std::string_view only = {}, bool withNextFrame = false);
    /// Why `pixels` cannot become the contents of external image `resource` of plan state `s`
    /// (setExternalImage(), and the pixels kept for a rebuild), or nothing.
    [[nodiscard]] static std::optional<std::string> externalPixelsProblem(const detail::PlanState& s,
                                                                          const std::string& resource,
                                                                          const ImageData& pixels);
    /// Setup steps for the next frame to record before its passes, with what they need kept
    /// alive (the staging buffers) until that frame has finished.
    struct PendingSetup {
        const detail::PlanState* state = nullptr;  ///< Dropped if the plan state is rebuilt first.
        std::string resource;  ///< The one external resource it sets up.
        std::function<void(detail::CommandSink&)> record;
        std::shared_ptr<void> keep;
    };
    /// In the order they were asked for, at most one per resource.
    std::vector<PendingSetup> pendingSetups;
    /// The staging buffers of the last upload that rode with a frame, to be reused.
    std::shared_ptr<std::vector<detail::OwnedBuffer>> lastStaging;
    /// A host-visible staging buffer of `bytes`: one of lastStaging's once its frame is done.
    [[nodiscard]] detail::OwnedBuffer spareStaging(VkDeviceSize bytes);
    /// Records `steps` (a setup or image-read plan over resources of `s`) with `record` for
    /// each step, submits once and waits. `copy` picks the per-slot copy of each resource.
    void submitAndWait(const std::function<void(detail::CommandSink&)>& record);

    // --- renderer_passes.cpp: recording code, render passes, framebuffers and barriers --------
    void buildPassStatic(detail::PlanState& s, size_t index);
    /// The recording code of `pass` (type `desc.type`) from options.passes; throws
    /// ExecutorError naming the pass when there is none.
    [[nodiscard]] std::unique_ptr<PassImplementation> implementationOf(const PlannedPass& pass, const PassDesc& desc) const;
    static VkAttachmentLoadOp loadOp(LoadOp op);
    static VkAttachmentStoreOp storeOp(StoreOp op);
    void buildRenderPass(detail::PlanState& s, detail::PassState& ps);
    void buildPassSlot(detail::PlanState& s, detail::PassState& ps, uint32_t slot);
    /// What a pass implementation sees of each usage: handles and a view of exactly the
    /// usage's subresources.
    void bindResources(detail::PlanState& s, detail::PassState& ps, uint32_t slot);
    /// createPipelines of every pass's recording code, with each frame slot's resources.
    void createPipelines(detail::PlanState& s);
    void createPipelines(detail::PlanState& s, detail::PassState& ps);

    // --- renderer_imports.cpp: swapping imported images between frames ------------------------
    /// importImage on a running plan: `image` replaces the image of plan resource `index` for
    /// the frames recorded from now on. The passes that use it get new recording code, views
    /// and framebuffers; what the frames already submitted use is retired, not destroyed.
    /// Checks everything (adoptImport) before changing anything.
    void swapImport(detail::PlanState& s, size_t index, const SharedImage& image);
    /// Destroys what swapImport retired once no submitted frame can use it any more.
    void releaseRetired();
    std::vector<detail::RetiredImport> retired;
    /// RendererAccess recorded its work into command buffers it does not fence.
    bool recordedElsewhere = false;

    // --- renderer_frame.cpp: frames -----------------------------------------------------------
    void createFrames();
    void ensureQueries(detail::FrameSlot& f, uint32_t count);
    void waitSlot(detail::FrameSlot& f);
    void collectTimings(detail::FrameSlot& f);
    [[nodiscard]] detail::VulkanCommands::Functions commandFunctions() const;
    /// Records the current plan's frame for `slot` into `cmd` (begun by the caller); with
    /// `frame`, timestamps and labels too.
    /// Records submit `submit` of binding slot `slot` into `cmd` (every submit when it is
    /// null: a hand-off of the whole frame into one command buffer).
    void recordFrame(VkCommandBuffer cmd, uint32_t slot, detail::FrameSlot* frame, std::optional<size_t> submit = {});
    /// The timeline semaphore of each queue kind (docs/queues.md), made with the first plan of
    /// several submits, and the value each has been signalled up to by submitted frames.
    std::array<owned::Semaphore, kQueueKinds> timelines;
    std::array<uint64_t, kQueueKinds> timelineValues{};
    void ensureTimelines();
    /// A command buffer of `f` for each of `submits`, from the pool of its queue.
    [[nodiscard]] std::vector<VkCommandBuffer> commandBuffers(detail::FrameSlot& f, std::span<const Submit> submits);
    [[nodiscard]] static size_t signallerOf(std::span<const Submit> submits, const SemaphoreOp& wait, size_t waiter);
    /// Frame slot f's binary semaphore `index`, made when first asked for.
    VkSemaphore binarySemaphore(detail::FrameSlot& f, size_t index);
    /// Records the current plan into frame slot `slot` (its fence waited for) with binding
    /// slot `binding` and submits it; with `target`, waiting for its acquire semaphore and
    /// signalling its render-complete semaphore.
    /// `background`: hold the last submit back (FrameSlot::held) until the others finish.
    void submitFrame(uint32_t slot, uint32_t binding, const PresentTarget* target, bool background = false);
    /// A frame whose recording threw: nothing of it is submitted. With `target`, a batch of no
    /// commands still waits for its acquire semaphore (signalling the slot's fence).
    void abandonFrame(detail::FrameSlot& f, const PresentTarget* target) noexcept;
    /// Set when a frame's recording threw: work the passes recorded for it never ran, and
    /// their implementations may count on it (a texture filled on first use), so the next
    /// frame makes them all again first (remakePassImplementations). A rebuild clears it.
    bool passesRecordedUnsubmitted = false;
    /// Waits for this renderer's frames and replaces every pass implementation of the plan
    /// state with a new one (createPipelines included). On failure throws, keeping the old ones.
    void remakePassImplementations();
    /// When releaseHeld() submits a held last submit.
    enum class HeldRelease {
        IfFinished,     ///< only if the rest of its frame has finished (never blocks)
        AfterFinished,  ///< waiting for the rest of its frame to finish
        Now,            ///< at once: work submitted next follows it on the GPU anyway
    };
    /// Submits `f`'s held last submit as `when` says. True when nothing is held any more.
    bool releaseHeld(detail::FrameSlot& f, HeldRelease when);
    void renderFrame(bool background = false);
    void waitIdle();

    // --- renderer_present.cpp: presenting -----------------------------------------------------
    /// Makes `images` the plan's Present resource and rebuilds the plan state (compiled again at
    /// their extent when it differs). On failure throws and keeps the old state and binding.
    void bindPresentImages(PresentImages images, const SwapchainAccess::Impl* swapchain);
    /// `compiled` at the present images' `extent`, for this device (forDevice); throws
    /// ExecutorError when it does not compile there.
    [[nodiscard]] CompiledGraph atPresentExtent(CompiledGraph compiled, VkExtent2D extent) const {
        return forDevice(std::move(compiled), extent);
    }
    /// Whether `compiled` presents another format, or with other usage, than the swapchain
    /// images it is bound to have (false when bound to the application's own images, or to
    /// none). Throws UnsupportedResourceError when the device's surface cannot give them.
    [[nodiscard]] bool needsOtherSwapchainImages(const CompiledGraph& compiled) const;
    /// Whether `need` asks for swapchain images of another format, or more usage, than
    /// `format` and `usage`. Throws UnsupportedResourceError when the device's surface cannot
    /// give them.
    [[nodiscard]] bool needsOtherImages(const PresentRequirements& need, VkFormat format, VkImageUsageFlags usage) const;
    /// Whether plan resource `index` of the running state is what this renderer presents (its
    /// present images, or the stand-in while awaiting new ones).
    [[nodiscard]] bool presents(uint32_t index) const;
    /// Whether the swapchain this renderer presents into was destroyed, with no images in its
    /// place yet: the plan state keeps views of its images until one is built for the next.
    [[nodiscard]] bool presentSwapchainDestroyed() const noexcept {
        return present && present->swapchain && present->swapchainLifetime.expired() && !present->awaitingImages;
    }
    /// Another renderer presenting into the bound swapchain re-created it: the images bound
    /// here are gone, and only the next frame into the swapchain binds the new ones.
    [[nodiscard]] bool presentImagesRecreatedElsewhere() const noexcept {
        return present && present->swapchain && !present->swapchainLifetime.expired() &&
               present->swapchain->imagesId != present->imagesId;
    }
    /// The checks of the binding against a plan state being built; sets presentResource.
    void describePresent(detail::PlanState& s) const;
    [[nodiscard]] uint32_t waitForFrameSlot();
    void renderFrame(const PresentTarget& target);
    PresentStatus renderFrame(Swapchain& swapchain);
};

}  // namespace skygraph
