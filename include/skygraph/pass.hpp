// Recording code for pass types: the executor-side half of a pass type, whose other half
// (slots, params) is the PassTypeInfo the compiler reads. Users add their own passes with
// the same two halves and register both through PassLibrary.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/pass_registry.hpp>
#include <skygraph/plan.hpp>
#include <skygraph/staging_buffer.hpp>
#include <skygraph/transfer_plans.hpp>

#include <vulkan/vulkan_core.h>

// Passes read their settings from PassDesc::params (e.g. `desc.params.value("samples", 64)`),
// which takes nlohmann::json's full definition; graph.hpp only names the type.
#include <nlohmann/json.hpp>

#include <any>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <typeindex>
#include <unordered_map>
#include <vector>

namespace skygraph {

class ShaderCompiler;

/// Values the application hands to passes for one frame (a camera, an exposure, a scene...),
/// stored by type. The renderer owns it; passes read it while renderFrame() records, so a value
/// set between frames applies from the next one. Not synchronized: use the renderer's thread.
/// The type is the key, so it must be a class of its own (`struct Exposure { float ev; }`): a
/// bare `set(1.0)` would store a double that `get<float>()` never finds, and two passes
/// wanting different floats would share one. A value is found by the exact type it was set
/// as, not by a base class.
class FrameData {
public:
    FrameData() = default;
    /// Not copyable or movable: the renderer's is the one passes read, so a copy
    /// (`auto data = renderer.frameData();`) would take values that no pass ever sees.
    FrameData(const FrameData&) = delete;
    FrameData& operator=(const FrameData&) = delete;

    /// What a FrameData stores: a class type, the key it is found by.
    template <typename T>
    static constexpr bool kKeyable = std::is_class_v<T>;

    /// Stores (replaces) the value of type T; the FrameData owns the copy.
    template <typename T>
        requires kKeyable<T>
    void set(T value) {
        values_[std::type_index(typeid(T))] = std::move(value);
    }
    /// The value of type T, or nullptr when none was set. The pointer is valid until a value
    /// of type T is set again or the FrameData is destroyed.
    template <typename T>
        requires kKeyable<T>
    [[nodiscard]] const T* get() const {
        auto it = values_.find(std::type_index(typeid(T)));
        return it == values_.end() ? nullptr : std::any_cast<T>(&it->second);
    }

private:
    std::unordered_map<std::type_index, std::any> values_;
};

/// One resource as a pass sees it through one of its usages. The renderer owns the handles and
/// the plan and graph the pointers point into; they stay valid for as long as the renderer may
/// call the pass implementation given them (do not destroy them).
struct BoundResource {
    const PlannedUsage* usage = nullptr;
    const ResourceDesc* desc = nullptr;
    VkImage image = VK_NULL_HANDLE;
    /// A view of exactly the usage's mips and layers (cube views for whole cubes that are
    /// sampled; 2D-array views for storage access to cube faces). VK_NULL_HANDLE for Transfer
    /// usages: copies take the image.
    VkImageView view = VK_NULL_HANDLE;
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{0, 0};  ///< Of the usage's base mip.
    /// Owned by the renderer: how many times it has replaced the resource's contents from
    /// outside the plan's passes (Renderer::setExternalImage(), updateExternalImage(),
    /// importImage(), the setup of a rebuilt plan). Read it while recording: a pass that builds
    /// on what earlier frames made of its inputs (PathTracePass accumulates) starts over when
    /// it changes. Null where nothing counts.
    const uint64_t* contentsReplaced = nullptr;
};

/// What a pass may use while creating pipelines. The struct and its spans are valid only
/// during the call; what they point to (pass, desc, the BoundResources, shaders) stays valid
/// for as long as the renderer may call the implementation, so it may keep those pointers.
struct PipelineContext {
    VkDevice device = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    /// The instance, and the queue family and queue the renderer submits to, for libraries
    /// that are initialised with them (Dear ImGui's Vulkan backend). A pass submits nothing.
    VkInstance instance = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    VkQueue queue = VK_NULL_HANDLE;
    /// For graphics passes (those with a ColorAttachment or DepthAttachment usage): the render
    /// pass the executor will begin around `record`, with one subpass whose colour attachments
    /// are the pass's ColorAttachment usages in usage order and whose depth attachment is its
    /// DepthAttachment usage. VK_NULL_HANDLE for others.
    VkRenderPass renderPass = VK_NULL_HANDLE;
    const PlannedPass* pass = nullptr;
    const PassDesc* desc = nullptr;
    std::span<const BoundResource> resources;  ///< Parallel to pass->usages (frame slot 0).
    /// The resources of every frame slot (RendererOptions::framesInFlight of them; while the
    /// renderer presents, one per frame slot and swapchain image, each used by that frame
    /// slot's frames only), each parallel to pass->usages; element 0 is `resources`. A slot's handles stay the same for
    /// the pass implementation's whole life: `record` for frame slot s (RecordContext::frameSlot)
    /// gets exactly frameSlots[s], so what a pass prepares per slot here (views, descriptor
    /// writes, scratch buffers) stays valid. The spans are valid only during the call.
    std::span<const std::span<const BoundResource>> frameSlots;
    VkExtent2D outputExtent{0, 0};  ///< The plan's output extent.
    ShaderCompiler* shaders = nullptr;
};

/// A sampled image that a pass owns (a model's texture, say), to be filled from the host:
/// RecordContext::fillSampledImages.
struct SampledImageFill {
    SampledImageShape shape;
    /// 2D, one layer, the full mip chain of `shape`, with TRANSFER_SRC, TRANSFER_DST and
    /// SAMPLED usage; never used before (its contents are discarded).
    VkImage image = VK_NULL_HANDLE;
    /// Mip 0's texels, rows tightly packed; read when the frame runs, so it must live (and not
    /// change) until the frame has finished.
    VkBuffer staging = VK_NULL_HANDLE;
};

/// What a pass may use while recording. The struct, `cmd`, its spans and recordInPassBarriers
/// are valid only during the call; the pointers and handles are the renderer's, as in
/// PipelineContext (`frame` is the renderer's FrameData).
struct RecordContext {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    const PlannedPass* pass = nullptr;
    const PassDesc* desc = nullptr;
    std::span<const BoundResource> resources;  ///< Parallel to pass->usages.
    uint32_t frameSlot = 0;  ///< Whose resources these are: PipelineContext::frameSlots[frameSlot].
    VkExtent2D renderArea{0, 0};  ///< Graphics passes: the framebuffer's extent.
    VkSampler linearSampler = VK_NULL_HANDLE;  ///< Trilinear, clamp to edge.
    VkSampler repeatSampler = VK_NULL_HANDLE;  ///< Trilinear, repeat in U, clamp in V (equirect).
    const FrameData* frame = nullptr;
    uint64_t frameIndex = 0;
    /// Records, outside any render pass (a graphics pass calls it from recordBeforeRenderPass),
    /// the compiler's plan for filling sampled images (planSampledImageUploads): each image's
    /// mip 0 copied from its staging buffer, the rest of its chain blitted down, and the
    /// barriers that leave it in SHADER_READ_ONLY_OPTIMAL, visible to the fragment and compute
    /// shaders of this frame and of later ones. A pass records no barrier of its own. Throws
    /// ExecutorError for shapes that plan refuses, inside the render pass (from record() of a
    /// graphics pass), and for a pass on a queue other than graphics.
    std::function<void(std::span<const SampledImageFill>)> fillSampledImages;
    /// Records the plan's in-pass barriers of this pass (Plan::inPassBarriers()). A pass with a
    /// ReadWrite transfer calls it once, between its copies out and its copies in; it is the
    /// only barrier a pass may record, and the executor provides it.
    std::function<void()> recordInPassBarriers;
    /// The pixels staged for this frame (Renderer::stageUpload) for resource `name`, or
    /// nullptr: what an UploadPass copies from. The pointer is valid during the call; the
    /// renderer keeps the buffer until the frame has finished.
    std::function<const StagingBuffer*(std::string_view name)> staged;

    /// The first usage filling `slot`, or nullptr. Repeated slots: `nth` picks which. The
    /// pointer is into `resources`: valid during the call only.
    [[nodiscard]] const BoundResource* slot(std::string_view name, size_t nth = 0) const noexcept;
};

/// The recording code of one pass instance. Created once per pass of a plan and owned by the
/// renderer, which destroys it with the plan state (a new plan, a resize, a shader reload) or,
/// if keepsSlotHandles(), when importImage swaps an image it uses, only once the GPU has
/// finished with what it recorded; not copyable. Vulkan objects
/// it creates are its own to destroy. Called on the thread that calls the renderer.
class PassImplementation {
public:
    PassImplementation() = default;
    virtual ~PassImplementation() = default;
    PassImplementation(const PassImplementation&) = delete;
    PassImplementation& operator=(const PassImplementation&) = delete;

    /// Builds pipelines: called once, after construction and before any record (a rebuild
    /// makes new implementations). Throwing fails that build, so the previous plan state keeps
    /// running; a std::exception comes out as an ExecutorError naming the pass.
    virtual void createPipelines(const PipelineContext& context) = 0;

    /// Records the pass's work. The executor has already recorded the plan's barrier batch
    /// and, for graphics passes, begun the render pass; it ends it afterwards. What this throws
    /// comes out of renderFrame() as it is, and that frame is not submitted: nothing any pass
    /// recorded for it runs. The renderer then makes every pass implementation again before
    /// its next frame, so an implementation is never called again after recording work that
    /// did not run (it may count on what it recorded before, a texture filled once, say).
    virtual void record(const RecordContext& context) = 0;

    /// Graphics passes only: records what Vulkan does not allow inside a render pass (copies,
    /// dispatches) before the executor begins it; `record` follows inside the render pass with
    /// the same context. The plan's barrier batch is already recorded. By default nothing.
    virtual void recordBeforeRenderPass(const RecordContext& context) { (void)context; }

    /// Whether the implementation keeps image or buffer handles from createPipelines (its
    /// PipelineContext::frameSlots, say in descriptor sets) rather than reading them from the
    /// RecordContext each time it records. One that keeps them is made again when
    /// Renderer::importImage swaps an image it uses; one that does not is kept, pipelines and
    /// all, and only its framebuffers change. By default true, the safe answer.
    [[nodiscard]] virtual bool keepsSlotHandles() const noexcept { return true; }
};

/// Makes the recording code of one pass whenever a renderer builds its plan state; it must not
/// return null (the renderer throws ExecutorError). What it throws comes out of the renderer
/// as an ExecutorError naming the pass. `desc` is the pass in the renderer's CompiledGraph:
/// valid for the whole life of the implementation.
using PassFactory = std::function<std::unique_ptr<PassImplementation>(const PassDesc&)>;

/// Pass types with both halves: the declaration the compiler checks graphs against, and the
/// factory the executor records with. Copyable; owns its entries.
class PassLibrary {
public:
    /// Generic and the built-in passes (docs/graph-format.md, "Built-in pass types"), each
    /// with its recording code; Generic's performs exactly the declared accesses. A new library
    /// the caller owns. Defined by the built-in passes' library (skygraph::passes): link it to
    /// call this.
    [[nodiscard]] static PassLibrary withBuiltins();
    /// The built-in Generic alone: a renderer given it records every pass type, built-in ones
    /// included, as Generic, performing exactly the declared accesses (what validating a
    /// graph's barriers wants). Static storage, valid for the program's life; defined beside
    /// withBuiltins().
    [[nodiscard]] static const PassLibrary& genericOnly();

    /// Registers a pass type; the library keeps both. Throws std::invalid_argument, registering
    /// nothing, when `factory` is empty, the name is taken, or PassRegistry::add rejects `info`.
    void add(PassTypeInfo info, PassFactory factory);

    /// The declarations, for loadGraphFile / parseGraph. The reference is valid while the
    /// library lives (and is not assigned to); add() extends what it holds.
    [[nodiscard]] const PassRegistry& registry() const noexcept { return registry_; }
    /// nullptr when the type has no recording code (a renderer then runs it with the
    /// library's "Generic"). The pointer is valid while the library lives (and is not assigned
    /// to).
    [[nodiscard]] const PassFactory* factory(std::string_view type) const noexcept;

private:
    PassRegistry registry_;
    std::map<std::string, PassFactory, std::less<>> factories_;
};

}  // namespace skygraph
