// The Renderer: runs a compiled graph on a Device. It records exactly the plan's barriers and
// derives no synchronization of its own.
#pragma once

#include <skygraph/compiled_graph.hpp>
#include <skygraph/device.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/image_data.hpp>
#include <skygraph/plan.hpp>
#include <skygraph/shared_image.hpp>
#include <skygraph/swapchain.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

class PassLibrary;  // skygraph/pass.hpp: pass implementations
class FrameData;    // skygraph/pass.hpp: per-frame values for pass implementations
class StagingBuffer;  // skygraph/staging_buffer.hpp: host pixels an UploadPass copies
class ShaderCompiler;  // skygraph/shader_compiler.hpp: GLSL to SPIR-V, and the sources it kept
class Renderer;

/// How a Renderer runs; what it runs (graph, options, output size) is the CompiledGraph.
struct RendererOptions {
    /// 1 to 8; the constructor throws otherwise.
    uint32_t framesInFlight = 2;
    /// Directory with the GLSL includes (shaders/); empty: ShaderCompiler::defaultIncludeDir().
    std::filesystem::path shaderDir;
    /// Where compiled SPIR-V is kept between runs: unset, ShaderCompiler::defaultCacheDir();
    /// an empty path, nowhere (every run compiles its shaders). With shaderCompiler, its own is
    /// kept instead.
    std::optional<std::filesystem::path> shaderCacheDir;
    /// Recording code by pass type; borrowed, must outlive the renderer. A type without a factory
    /// runs with the library's "Generic" (a warning says so, once per type, unless the library
    /// has Generic alone, as PassLibrary::genericOnly() does: it asks for exactly that). Null: no
    /// recording code, so a plan with passes throws.
    const PassLibrary* passes = nullptr;
    /// Borrowed during construction only: the renderer starts out bound to this swapchain's
    /// current images (it keeps views of them, as after a frame into it: Swapchain says how long
    /// the swapchain must live then), so that its first renderFrame(*presentTo) builds nothing
    /// again; e.g. a new renderer for a window that is already presenting. The constructor then
    /// compiles the graph at the images' extent (compiled() has that size) and throws
    /// ExecutorError when it does not compile there. When the swapchain has no fitting images
    /// (paused, out of date, or made for another format or usage) nothing is bound and the first
    /// frame binds, as with null; a format or usage the surface cannot give throws
    /// ExecutorError here, as setGraph() does.
    Swapchain* presentTo = nullptr;
    /// GPU timestamps around each pass (lastTimings(), completedTimings()). Off, a frame
    /// writes none and none is read back, which on some drivers waits for whatever the queue
    /// runs: for a renderer whose frames run beside another's (a background bake).
    bool timestamps = true;
    /// The compiler another renderer built with (Renderer::shaderCompiler(), of a running
    /// renderer or of one that is gone), shared. The new renderer builds from the shader sources
    /// it keeps and from its include directory (`shaderDir` and `shaderCacheDir` are not used),
    /// as that renderer's setGraph() with ShaderSources::Cached would, until it reads its shaders
    /// again: e.g. an application replacing its renderer while a shader on disk is half edited.
    /// Null: the shaders are read from `shaderDir`.
    std::shared_ptr<ShaderCompiler> shaderCompiler;
};

/// What renderFrame(Swapchain&) did.
enum class PresentStatus : uint8_t {
    Presented,  ///< A frame was rendered and queued for presentation.
    /// Nothing was rendered: the window has no size (0x0, e.g. minimized), or the surface
    /// kept going out of date while the swapchain was re-created for it.
    Paused,
};

/// When Renderer::updateExternalImage() copies new pixels into the image.
enum class UploadTiming : uint8_t {
    /// Submitted and waited for before the call returns, after this renderer's frames.
    Now,
    /// Recorded at the start of the next frame, and nothing waits; where the copy cannot ride
    /// with a frame, as Now (Renderer::updateExternalImage() says when).
    WithNextFrame,
};

/// GPU time of one pass in the last completed frame of a slot.
struct PassTiming {
    std::string pass;
    double milliseconds = 0.0;
};

/// Runs one compiled graph. Owns all images, buffers, pipelines and command buffers it
/// creates, and its CompiledGraph; borrows `device` (which must outlive it). Not copyable.
/// It runs only plans compiled with its device's memory model (Device::memoryModel()), since
/// a plan places its transient resources in shared heaps by their memory requirements, and,
/// for a plan that submits to more than one queue, with its device's queue families
/// (Device::queueFamilies(), which decide ownership transfers): a CompiledGraph compiled with
/// other CompileOptions::memory or queueFamilies is compiled again with the device's, and
/// compiled() reports that one, the plan that runs.
/// The renderer's plan state (the compiled graph, the images, the pipelines) is rebuilt, when
/// they succeed, by exactly these calls: setGraph(), resize(), reloadShaders(),
/// setPresentImages() (every call, even with images of an unchanged extent), and
/// renderFrame(Swapchain&) whenever it binds the swapchain's images: its first frame into a
/// swapchain the renderer is not already bound to (RendererOptions::presentTo), and its first
/// frame after the swapchain was re-created (out of date, suboptimal, Swapchain::resize, or a
/// frame into it whose recording threw). HotReloader::poll() calls setGraph() and
/// reloadShaders(). A rebuild waits for this renderer's own frames, not for other renderers'
/// (a background bake may go on running); only re-creating a Swapchain waits for the whole
/// queue (renderFrame(Swapchain&)). After a rebuild, references
/// returned by compiled(), graph(), plan() and setupPlan() are invalid, and images shared
/// before are no longer written by this renderer. A failed call keeps the old state. Names
/// passed in are read during the call only. Use from one thread at a time; renderers on one
/// Device share its queues, which Vulkan lets one thread use at a time, so calls to all of
/// them, and to the Device and its Swapchains and HotReloaders, must not overlap, whichever
/// threads make them (Device's comment says so too).
class Renderer {
public:
    /// Takes `compiled` (compiled again with the device's memory model and queue families unless
    /// it was: see the class comment); creates resources, pipelines and per-frame state at its output size
    /// and runs its plan's setup (planSetup), waiting for it. Throws ExecutorError (e.g.
    /// framesInFlight outside 1..8, a pass type without recording code, a format the device
    /// cannot use as the plan requires, a read-back of a format readback() does not convert,
    /// a pass's createPipelines failing, a pass whose usages do not fill its type's slots as the
    /// type declares them, a pass past the device's attachment or descriptor limits). Rebuilds
    /// of the plan state throw the same.
    Renderer(Device& device, CompiledGraph compiled, RendererOptions options = {});
    /// Waits for this renderer's own frames to finish, not for other renderers' (a background
    /// bake may go on running), then destroys what the renderer owns; images shared with
    /// other renderers live on while they use them. A renderer that has submitted to several
    /// queues (a plan of any of its graphs did) also waits for each of those queues to be
    /// idle, so then it waits for other renderers' work on them too. Never throws: when the
    /// wait fails (a lost device), it logs why and waits for the whole device instead.
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Waits for the frame slot to be free, records the plan and submits. Non-blocking
    /// otherwise: up to framesInFlight frames run at once. Throws ExecutorError for a Vulkan
    /// failure, once the renderer presents (renderFrame(Swapchain&), setPresentImages), and
    /// before it has present images when the plan was compiled to present (without
    /// CompileOptions::presentReplacement), submitting nothing. What a pass implementation
    /// throws while the frame is recorded comes out as it is, and the renderer stays usable:
    /// the frame is not submitted (frameCount() does not count it,
    /// readback() still reads the frame before), what was to ride with it (stageUpload(),
    /// updateExternalImage() with WithNextFrame) rides with the next one, and since the work
    /// every pass recorded for it never runs, the next frame first waits for this renderer's
    /// frames and makes every pass implementation again (PassFactory, then createPipelines;
    /// should that throw, the frame throws it and the next tries again). Presenting, see
    /// renderFrame(Swapchain&) and renderFrame(const PresentTarget&) for the image.
    void renderFrame();
    /// Presents a frame through `swapchain` (made for this renderer's device and plan): waits
    /// for the frame slot, acquires an image, records the plan into it, submits waiting for
    /// the acquire at the stages of the plan's first use of the image and signalling the
    /// image's render-complete semaphore, and presents. The plan's Present resource is the
    /// acquired image (no copy of it is made). When the swapchain is out of date, suboptimal or
    /// resized (Swapchain::resize), it is re-created first and the plan recompiled at its new
    /// extent (as resize() does). Binding the swapchain's images (the first frame into it,
    /// unless RendererOptions::presentTo bound them, and the first after each re-creation)
    /// rebuilds the plan state, which invalidates references from compiled(), graph() and
    /// plan(). Returns Paused, rendering nothing, while the window is 0x0. Re-creating the
    /// swapchain waits for the Device's queue to be idle (vkQueueWaitIdle: presents have no
    /// fence to wait for), and so for other renderers' work on it too.
    /// Borrows the swapchain for the call; the renderer keeps views of its images until it
    /// renders into another one (Swapchain says how to replace one). Throws ExecutorError (e.g. the
    /// plan does not compile at the new size: the old plan stays, and the next call tries again).
    /// When a pass throws while the frame is recorded (renderFrame() says what else happens),
    /// the acquired image is not presented, but the frame's wait for its acquire is still
    /// submitted, and the swapchain is marked for re-creation, which gives the image back:
    /// the next call re-creates it, and so rebuilds the plan state.
    PresentStatus renderFrame(Swapchain& swapchain);
    /// Presenting into images of the application's own (e.g. its own VkSwapchainKHR's): they
    /// become the plan's Present resource, and the plan state is rebuilt on every call,
    /// compiled again at their extent if it differs (references from compiled(), graph() and
    /// plan() are invalid afterwards). Their format must be the Present resource's and their
    /// usage must include presentRequirements(compiled()).usage. Call it again after
    /// re-creating them.
    /// The images are borrowed: keep them alive while this renderer renders into them. Waits
    /// for every submitted frame first; once it returns, the renderer holds no view of the
    /// images given before, which may then be destroyed (their presents done). Throws
    /// ExecutorError on a mismatch, keeping the old state (and the old images in use).
    void setPresentImages(PresentImages images);
    /// Waits until the frame slot that the next frame records into is free (its previous frame
    /// has finished) and returns its index, below framesInFlight. Semaphores that slot's last
    /// frame waited for may then be reused: with images of your own, acquire with a semaphore
    /// per frame slot after this call.
    [[nodiscard]] uint32_t waitForFrameSlot();
    /// Renders one frame into `target.image` of the images given to setPresentImages: waits
    /// for `target.acquired` at the stages of the plan's first use of the image, records the
    /// plan (its final barrier leaves the image in PRESENT_SRC_KHR) and signals
    /// `target.renderComplete`; the caller presents (vkQueuePresentKHR waiting for it) on
    /// Device::queue(). The semaphores are borrowed for the submit: the caller owns them and
    /// keeps them until that frame and its present are done (waitIdle(), then the queue's
    /// vkQueueWaitIdle). Throws ExecutorError without setPresentImages, for an index out of
    /// range or a null semaphore, submitting nothing. When a pass throws while the frame is
    /// recorded (renderFrame() says what else happens), the frame still submits its wait for
    /// `target.acquired` (so the semaphore may be acquired with again once
    /// waitForFrameSlot() returns that slot, which the next frame uses again) but does not
    /// signal `target.renderComplete`: do not present the image. It stays acquired; re-create
    /// the swapchain (after waitIdle() and the queue's vkQueueWaitIdle) and call
    /// setPresentImages() to have it back.
    void renderFrame(const PresentTarget& target);
    /// Renders one frame beside other renderers' frames, for work such as an environment
    /// re-bake on the compute queue (docs/queues.md, "Background frames"): as renderFrame(),
    /// but the frame's last submit, which on a plan of several queues waits on the graphics
    /// queue for the others and would hold up every frame submitted there after it, is held
    /// back. finishBackgroundFrame() submits it. Headless renderers only; throws ExecutorError
    /// otherwise. A plan of one submit is submitted whole.
    void renderFrameInBackground();
    /// Never blocks. Submits the background frame's held submit once the rest of that frame
    /// has finished on the GPU, and returns true then (and when nothing is held): work
    /// submitted to Device::queue() afterwards, such as another renderer's next frame, is
    /// ordered after the whole frame, and shareImage() may hand its images on. False while
    /// the other queues still work. waitIdle() and every call that waits for a frame submit it
    /// too, waiting; this renderer's next frame submits it first, without waiting (that frame
    /// follows the whole of this one), so work submitted to Device::queue() after that waits
    /// for the rest of this frame on the GPU.
    [[nodiscard]] bool finishBackgroundFrame();
    /// Waits until every submitted frame has finished.
    void waitIdle();
    /// Waits for the most recent frame and returns a copy, owned by the caller, of what its one
    /// Readback step copied (the plan was compiled with one name in CompileOptions::readbacks).
    /// Throws ExecutorError when the plan reads back no image or several, or when no frame has
    /// been rendered since the plan state was built or setExternalImage() last ran.
    [[nodiscard]] ImageData readback();
    /// The same for the read-back of `resource`, one of CompileOptions::readbacks.
    [[nodiscard]] ImageData readback(std::string_view resource);
    /// Waits for every submitted frame, then copies every mip and layer of the image
    /// `resource` to the host (element mip * layers + layer), e.g. an environment cube and
    /// its mip chain; the caller owns the copies. The steps and their barriers are the plan of
    /// planImageRead. The image is left in its end-of-frame layout (the plan's final layout).
    /// Throws ExecutorError for an unknown name, a buffer, an image no frame has written, a
    /// transient whose memory another resource takes over later in the frame, the presented
    /// image (the Present resource of a presenting renderer: the presentation engine owns it
    /// after the frame), a format it does not convert (integer, stencil, packed; the message
    /// lists those it does), or when no frame has been rendered since the plan state was built
    /// or setExternalImage().
    [[nodiscard]] std::vector<ImageData> readImage(const std::string& resource);
    /// Compiles the graph again at a new output extent (CompiledGraph::resized, with the running
    /// options and so the device's memory model) and rebuilds the plan state. Throws
    /// ExecutorError when the graph does not compile at that size or the device cannot hold
    /// it; the old plan keeps running then. A presenting renderer follows its images' extent
    /// instead (a size other than theirs throws ExecutorError). Waits for this renderer's
    /// frames, not for other renderers'.
    void resize(uint32_t width, uint32_t height);
    /// Where setGraph() takes its shaders from.
    enum class ShaderSources : uint8_t {
        Cached,  ///< shader files read before are not read again: edits since are not seen
        Reread,  ///< every shader read and compiled again, as reloadShaders() does
    };
    /// Takes `compiled` in place of what runs (e.g. after a hot reload), once every submitted
    /// frame of this renderer has finished; compiled again with the device's memory model
    /// unless it was (the class comment), and, while the renderer presents, at its present
    /// images' extent (as the constructor does with RendererOptions::presentTo). On failure
    /// throws ExecutorError (also when the graph does not compile at that extent, or when its
    /// Present resource wants another format or usage than the application's own present
    /// images have, or than the device's surface can give) and keeps the old plan and pipelines
    /// running: with ShaderSources::Reread, a new graph and edited shaders take effect together
    /// or not at all. A graph that presents another format or usage than the Swapchain's
    /// images the renderer is bound to is installed with a stand-in for them: the next
    /// renderFrame(swapchain) re-creates the swapchain for it, as a new renderer's first frame
    /// would; until then the renderer presents as before (renderFrame() and
    /// renderFrame(const PresentTarget&) throw, resize() takes only its extent).
    void setGraph(CompiledGraph compiled, ShaderSources shaders = ShaderSources::Cached);
    /// Reads every shader again from the shader directory and rebuilds the plan state (after
    /// an edit), once this renderer's frames have finished. On failure throws ExecutorError
    /// with glslang's log; the old pipelines keep running. Every other rebuild (resize(),
    /// setPresentImages(), a swapchain's new images, setGraph() with ShaderSources::Cached)
    /// builds from the shader sources the running pipelines were built from, so a shader
    /// broken on disk fails only this call.
    void reloadShaders();
    /// Whether a shader file the running pipelines were built from, or a file it includes,
    /// reads differently on disk now (ShaderCompiler::keptFilesChanged): e.g. whether an edit
    /// in the shader directory concerns this renderer, for one that renders once (a bake) and
    /// would render again rather than reload.
    [[nodiscard]] bool shadersChangedOnDisk() const;
    /// Imports a loaded texture: `pixels` (float RGBA, as stored; the renderer keeps them)
    /// become the contents of mip 0 (every layer) of the external image `resource`, by an Upload
    /// step of the plan's setup, now and whenever the plan is re-installed. Waits for this
    /// renderer's own frames, not for other renderers' (one that reads an image this renderer
    /// shares must have finished before: the caller orders that), then runs the whole setup
    /// again and waits for it, so every external resource it covers gets its first contents
    /// back. Throws ExecutorError for a wrong name or size, `pixels.rgba` of another length than
    /// width x height x 4, an image format pixels cannot be uploaded to, or an image imported
    /// from another renderer (importImage(): its pixels are the producer's). A rebuild whose
    /// plan the kept pixels no longer fit throws too (forgetExternalImage()).
    void setExternalImage(const std::string& resource, ImageData pixels);
    /// Undoes setExternalImage() for `resource` from the next time the setup runs (a rebuild,
    /// which the class comment lists, or setExternalImage() of any resource): it gives the
    /// image its clear value or grey, as before the first pixels. Until then the frames keep
    /// reading the pixels.
    /// Pixels that no longer fit (an output-sized image, before a resize; a resource a new
    /// graph makes transient) fail every rebuild; forget them, rebuild, then give pixels that
    /// fit. Throws ExecutorError when `resource` has no pixels from setExternalImage().
    void forgetExternalImage(const std::string& resource);
    /// New pixels for external image `resource`, which setExternalImage() gave pixels before:
    /// one Upload step of the setup and its barriers, every other resource left as it is (so
    /// images this renderer shares keep their contents). The pixels go to a staging buffer
    /// now. With UploadTiming::Now the call waits for this renderer's frames (not for other
    /// renderers'), then submits the copy and waits for it. With WithNextFrame the copy is
    /// recorded at the start of the next frame's first submit, before its passes, and nothing
    /// waits: frames already submitted read the old pixels, and the copy's barriers order it
    /// after them. Updates of several resources before a frame all ride with it; a later one
    /// of the same resource replaces the earlier. Where the copy cannot ride with a frame (an
    /// image with a copy per frame slot, or a plan that submits to a queue other than
    /// Device::queue(), whose earlier frames' work those barriers do not order) it is
    /// uploaded as with Now. Throws ExecutorError as setExternalImage() does, and for a
    /// resource without pixels yet.
    void updateExternalImage(const std::string& resource, ImageData pixels, UploadTiming timing = UploadTiming::Now);
    /// Pixels for the next frame's UploadPass that writes `resource` (docs/graph-format.md,
    /// "Built-in pass types"): mip 0 of every layer, rows tightly packed, in the image's format
    /// (the whole buffer, for a buffer resource). Only that frame copies them:
    /// stage again before each frame whose plan runs the pass. The renderer holds `pixels`
    /// until the copy has finished on the GPU; write it no sooner. Unlike
    /// updateExternalImage(), nothing runs outside the plan, and the copy runs on whatever
    /// queue the graph puts the pass (a transfer queue copies beside the frames). Throws
    /// ExecutorError, staging nothing, for a resource the plan does not have or that no
    /// UploadPass of it writes (nothing would copy the pixels), a buffer of another size
    /// than the resource needs, or a buffer of another device.
    void stageUpload(const std::string& resource, std::shared_ptr<const StagingBuffer> pixels);
    /// The bytes stageUpload() takes for `resource`: width x height x layers x texel bytes
    /// of an image, the size of a buffer. Throws ExecutorError for a resource the plan does
    /// not have.
    [[nodiscard]] VkDeviceSize stagingBytes(const std::string& resource) const;
    /// Shares the image of `resource`, an external image this plan exports (`final` set),
    /// with another renderer on the same Device. It holds this frame's contents once the
    /// frames that write it have finished (waitIdle()), in the layout of its `final` state.
    /// The handle keeps the image alive after this renderer rebuilds or is destroyed, but only
    /// the current plan state's image is written: share again after a rebuild. Throws
    /// ExecutorError for a resource that is not an exported external image of the current
    /// plan, and while a background frame (renderFrameInBackground()) has not been finished:
    /// call finishBackgroundFrame() until it returns true, then share.
    [[nodiscard]] SharedImage shareImage(const std::string& resource) const;
    /// Makes the external image `resource` use `image` instead of the one it uses now, from
    /// the next frame on and whenever the plan is re-installed, and keeps a share of it. The
    /// graph must only read it, its format, extent, mips, layers and sharing must match, and it
    /// must arrive in the layout the producer leaves it in (`initial` here = `final` there).
    /// The caller orders the two renderers' work: the producer's frames must have finished
    /// (its waitIdle()), or its background frame been finished (finishBackgroundFrame()),
    /// before this renderer's next frame. Neither waits nor rebuilds: frames already submitted
    /// keep the image they were recorded with, which stays alive until they finish. Pixels of
    /// updateExternalImage() waiting for the next frame are dropped. While the swapchain this
    /// renderer presents into is destroyed, the import waits for the plan state built for the
    /// next one, as for a culled resource. Throws
    /// ExecutorError for an empty handle or on any mismatch, keeping the old image; when the
    /// recording code made again for the new image fails (its factory's exception passes on,
    /// createPipelines' as an ExecutorError naming the pass), the old image, with everything
    /// built for it, keeps running. For a
    /// resource the current plan does not use (its passes culled), the image is checked
    /// against the graph's declaration (device, format, extent, mips, layers) and kept for the
    /// rebuild that brings the resource back; what only a plan that uses it can say (usages,
    /// layout, sharing, being written) is checked by that rebuild, which throws on a mismatch
    /// (forgetImport()).
    void importImage(const std::string& resource, SharedImage image);
    /// Undoes importImage() for `resource` from the next rebuild on (the class comment lists
    /// the calls that rebuild): the rebuilt plan makes and sets up an image of its own for it,
    /// as before the first import, and drops its share of the imported one. Until then the
    /// frames go on reading the imported image. An import whose image no longer fits (an
    /// output-sized one, before a resize) fails every rebuild; forget it, rebuild, then import
    /// one that fits. Throws ExecutorError when `resource` has no imported image.
    void forgetImport(const std::string& resource);
    /// Values handed to pass implementations while recording (camera, exposure, ...). Owned
    /// by the renderer; the reference is valid, and the values kept, for its whole life,
    /// rebuilds included.
    [[nodiscard]] FrameData& frameData() noexcept;
    /// What runs: the graph, its compile options and the plan, always compiled with the
    /// device's memory model (so it may be a recompile of what was given). Owned by the
    /// renderer; valid until the plan state is rebuilt (the class comment lists the calls that
    /// rebuild it). Copy it to keep it longer.
    [[nodiscard]] const CompiledGraph& compiled() const noexcept;
    /// compiled().graph(): the graph the current plan was compiled from. Owned by the renderer;
    /// valid until the plan state is rebuilt, as compiled() is.
    [[nodiscard]] const GraphDesc& graph() const noexcept;
    /// Per-pass GPU times of the most recently submitted frame (waits for it to finish),
    /// copied. Empty before the first frame of the current plan state. Passes on a queue whose
    /// family has no timestamps are left out.
    [[nodiscard]] std::vector<PassTiming> lastTimings();
    /// Per-pass GPU times of the newest frame seen finished, without waiting (up to frames
    /// in flight behind: what a live overlay shows). The reference is valid, and what it holds
    /// unchanged, until the next call that waits for a frame (renderFrame() of any kind,
    /// renderFrameInBackground(), waitForFrameSlot(), waitIdle(), lastTimings(), readback(),
    /// readImage(), setExternalImage(), updateExternalImage()) or rebuilds the plan state
    /// (the class comment lists the calls that do).
    [[nodiscard]] const std::vector<PassTiming>& completedTimings() const noexcept;

    /// compiled().plan(): the current plan. Owned by the renderer; valid until the plan state
    /// is rebuilt (the class comment lists the calls that rebuild it). A copy stands alone.
    [[nodiscard]] const Plan& plan() const noexcept;
    /// The setup that ran before the current plan's first frame (planSetup of plan(), with
    /// this renderer's uploads and imports). Owned by the renderer; valid until the plan state
    /// is rebuilt or setExternalImage() runs it again.
    [[nodiscard]] const Plan& setupPlan() const noexcept;
    /// Frames submitted since construction, rebuilds included.
    [[nodiscard]] uint64_t frameCount() const noexcept;
    /// The directory its shaders are read from: RendererOptions::shaderDir, the default an
    /// empty one stands for, or that of RendererOptions::shaderCompiler. A copy.
    [[nodiscard]] std::filesystem::path shaderDir() const;
    /// The compiler the running pipelines were built with, which keeps the shader sources they
    /// were built from (ShaderCompiler::source): for RendererOptions::shaderCompiler of a
    /// renderer made later, after this one is gone too. Shared with this renderer until it
    /// reads its shaders again (reloadShaders(), setGraph() with ShaderSources::Reread), which
    /// it does with a new compiler, leaving this one as it was.
    [[nodiscard]] std::shared_ptr<ShaderCompiler> shaderCompiler() const;
    /// RendererOptions::passes: borrowed, null when the renderer has no recording code.
    [[nodiscard]] const PassLibrary* passes() const noexcept;

private:
    struct Impl;
    friend struct RendererAccess;  // the implementation's own access; not part of the API
    std::unique_ptr<Impl> impl_;
};

/// Why Renderer::readback() cannot convert image `resource` of `format`, in the words a renderer
/// compiled with that read-back throws; empty when it can. For refusing before a device is made.
[[nodiscard]] std::string readbackProblem(const std::string& resource, VkFormat format);

}  // namespace skygraph
