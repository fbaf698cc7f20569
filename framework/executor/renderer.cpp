// The Renderer: the public API over Renderer::Impl (renderer_impl.hpp), and building the state
// of one plan.
#include "renderer_impl.hpp"
#include "renderer_access.hpp"
#include "swapchain.hpp"

#include <skygraph/format.hpp>
#include <skygraph/transfer_plans.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <cstring>
#include <exception>

namespace skygraph {

using namespace detail;

std::unique_ptr<PlanState> Renderer::Impl::build(CompiledGraph compiled) {
    if (compiled.outputWidth() == 0 || compiled.outputHeight() == 0)
        throw ExecutorError("output extent must be at least 1x1");
    // A plan state then renders into a stand-in, as while awaiting images of another format,
    // and makes no view of the destroyed ones.
    if (presentImagesRecreatedElsewhere()) present->awaitingImages = true;
    // Placements are only as good as the requirements they were made with: this device's.
    auto s = std::make_unique<PlanState>(forDevice(std::move(compiled)));
    describeResources(*s);
    for (size_t i = 0; i < s->plan.passes().size(); ++i) buildPassStatic(*s, i);
    buildSized(*s);
    createPipelines(*s);
    return s;
}

namespace {

/// Why a read finds nothing: no frame has been rendered into the images it would read.
constexpr const char* kNoFrameYet =
    "no frame has been rendered since the renderer was made or last set up its images (setGraph, resize, "
    "reloadShaders, a new swapchain or setExternalImage)";

float halfToFloat(uint16_t h) {
    const uint32_t sign = (h & 0x8000u) << 16;
    const uint32_t exp = (h >> 10) & 0x1fu;
    const uint32_t mant = h & 0x3ffu;
    uint32_t bits;
    if (exp == 0) {
        if (mant == 0) {
            bits = sign;
        } else {
            float v = std::ldexp(static_cast<float>(mant), -24);
            return (h & 0x8000u) ? -v : v;
        }
    } else if (exp == 31) {
        bits = sign | 0x7f800000u | (mant << 13);
    } else {
        bits = sign | ((exp + 112) << 23) | (mant << 13);
    }
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

/// Writes texel `i` of `bytes` as RGBA floats into `px`.
using TexelReader = void (*)(const uint8_t* bytes, size_t i, float* px);

/// The reader of one texel of `format`, or null for a format read-back does not convert
/// (integer, stencil, packed): the one list of what readback() and readImage() read.
TexelReader texelReader(VkFormat format) noexcept {
    switch (format) {
        case VK_FORMAT_R8G8B8A8_UNORM:
        case VK_FORMAT_R8G8B8A8_SRGB:
            return [](const uint8_t* bytes, size_t i, float* px) {
                for (size_t c = 0; c < 4; ++c) px[c] = bytes[i * 4 + c] / 255.0f;
            };
        case VK_FORMAT_B8G8R8A8_UNORM:
        case VK_FORMAT_B8G8R8A8_SRGB:
            return [](const uint8_t* bytes, size_t i, float* px) {
                px[0] = bytes[i * 4 + 2] / 255.0f;
                px[1] = bytes[i * 4 + 1] / 255.0f;
                px[2] = bytes[i * 4 + 0] / 255.0f;
                px[3] = bytes[i * 4 + 3] / 255.0f;
            };
        case VK_FORMAT_R16G16B16A16_SFLOAT:
            return [](const uint8_t* bytes, size_t i, float* px) {
                uint16_t h[4];
                std::memcpy(h, bytes + i * 8, 8);
                for (size_t c = 0; c < 4; ++c) px[c] = halfToFloat(h[c]);
            };
        case VK_FORMAT_R32G32B32A32_SFLOAT:
            return [](const uint8_t* bytes, size_t i, float* px) { std::memcpy(px, bytes + i * 16, 16); };
        case VK_FORMAT_R32G32_SFLOAT:  // e.g. a BRDF table
            return [](const uint8_t* bytes, size_t i, float* px) {
                std::memcpy(px, bytes + i * 8, 8);
                px[2] = 0.0f;
                px[3] = 1.0f;
            };
        case VK_FORMAT_R16G16_SFLOAT:  // e.g. a BRDF table
            return [](const uint8_t* bytes, size_t i, float* px) {
                uint16_t h[2];
                std::memcpy(h, bytes + i * 4, 4);
                px[0] = halfToFloat(h[0]);
                px[1] = halfToFloat(h[1]);
                px[2] = 0.0f;
                px[3] = 1.0f;
            };
        case VK_FORMAT_R32_SFLOAT:
        case VK_FORMAT_D32_SFLOAT:
            return [](const uint8_t* bytes, size_t i, float* px) {
                std::memcpy(px, bytes + i * 4, 4);
                px[1] = px[2] = 0.0f;
                px[3] = 1.0f;
            };
        case VK_FORMAT_R8_UNORM:
            return [](const uint8_t* bytes, size_t i, float* px) {
                px[0] = bytes[i] / 255.0f;
                px[1] = px[2] = 0.0f;
                px[3] = 1.0f;
            };
        default: return nullptr;
    }
}

}  // namespace

namespace detail {

bool readsBack(VkFormat format) noexcept { return texelReader(format) != nullptr; }

std::string notReadBackable(const std::string& resource, VkFormat format) {
    std::string formats;
    for (const FormatInfo& f : knownFormats())
        if (readsBack(f.format)) formats += (formats.empty() ? "" : ", ") + std::string(f.name);
    return "cannot read back '" + resource + "': its format " + formatName(format) + " is not supported for read-back, which converts " + formats;
}

}  // namespace detail

std::string readbackProblem(const std::string& resource, VkFormat format) {
    return detail::readsBack(format) ? std::string() : detail::notReadBackable(resource, format);
}

namespace {

ImageData convertPixels(const void* data, uint32_t width, uint32_t height, VkFormat format,
                        const std::string& name) {
    const TexelReader read = texelReader(format);
    if (!read) throw ExecutorError(notReadBackable(name, format));
    ImageData out;
    out.width = width;
    out.height = height;
    out.format = format;
    out.rgba.resize(size_t(width) * height * 4);
    const auto* bytes = static_cast<const uint8_t*>(data);
    const size_t n = size_t(width) * height;
    for (size_t i = 0; i < n; ++i) read(bytes, i, &out.rgba[i * 4]);
    return out;
}

}  // namespace

Renderer::Renderer(Device& device, CompiledGraph compiled, RendererOptions options) {
    if (options.framesInFlight == 0 || options.framesInFlight > 8)
        throw ExecutorError("framesInFlight must be between 1 and 8");
    impl_ = std::make_unique<Impl>(device, std::move(options));
    Impl& d = *impl_;
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_LINEAR;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    sci.maxLod = VK_LOD_CLAMP_NONE;
    VkSampler sampler;
    vk::check(vkCreateSampler(d.vkd, &sci, nullptr, &sampler), "vkCreateSampler");
    d.linearSampler = owned::Sampler(d.vkd, sampler);
    sci.addressModeU = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    vk::check(vkCreateSampler(d.vkd, &sci, nullptr, &sampler), "vkCreateSampler");
    d.repeatSampler = owned::Sampler(d.vkd, sampler);
    d.createFrames();
    if (Swapchain* presentTo = d.options.presentTo) {
        const SwapchainAccess::Impl& sc = SwapchainAccess::impl(*presentTo);
        if (&sc.device != &device) throw ExecutorError("RendererOptions::presentTo: a swapchain of another device");
        // A format or usage the surface cannot give fails here, as in setGraph, and not at the
        // first frame, which re-creates the swapchain for it.
        const PresentRequirements need = presentRequirements(compiled);
        (void)d.needsOtherImages(need, sc.requirements.format, sc.requirements.usage);
        if (!sc.needsRecreate(need) && !sc.paused()) {
            compiled = d.atPresentExtent(std::move(compiled), sc.extent);
            d.present = Impl::PresentBinding{PresentImages{sc.images, sc.requirements.format, sc.extent, sc.requirements.usage},
                                             &sc, sc.imagesId, sc.lifetime};
        }
    }
    d.state = d.build(std::move(compiled));
}

Renderer::~Renderer() {
    if (!impl_) return;
    // Its own frames are fenced; work it recorded into the application's command buffers
    // is not, so then only an idle device is safe. Waiting for its frames alone leaves other
    // renderers' frames running (a background bake that goes while frames render).
    if (impl_->recordedElsewhere) {
        vkDeviceWaitIdle(impl_->vkd);
        return;
    }
    try {
        impl_->waitIdle();
    } catch (const std::exception& e) {
        // A lost device fails the fence waits, most often while a failed frame unwinds past
        // this renderer: a destructor must not throw, and an idle device (or a lost one, whose
        // work counts as done) is still the point at which its objects may go.
        spdlog::warn("destroying a renderer: {}; waiting for the device to be idle instead", e.what());
        vkDeviceWaitIdle(impl_->vkd);
        return;
    }
    // A plan on several queues orders them with the renderer's timeline semaphores. The spec
    // lets a semaphore go once the batches that use it have completed, which the fences show;
    // lavapipe's queue threads still release their hold on a waited-for semaphore after the
    // batch's fence signals (its mutex was seen locked after the semaphore was freed: the heap
    // corrupted, or the queue deadlocked). So every queue drains first, at this one point.
    if (impl_->timelines[0])
        for (size_t k = 0; k < kQueueKinds; ++k) {
            const VkQueue q = impl_->dev.queues[k];
            bool seen = false;
            for (size_t j = 0; j < k; ++j) seen |= impl_->dev.queues[j] == q;
            if (!seen && q != VK_NULL_HANDLE) vkQueueWaitIdle(q);
        }
}

void Renderer::renderFrame() { impl_->renderFrame(); }
PresentStatus Renderer::renderFrame(Swapchain& swapchain) { return impl_->renderFrame(swapchain); }
void Renderer::renderFrame(const PresentTarget& target) { impl_->renderFrame(target); }
void Renderer::setPresentImages(PresentImages images) { impl_->bindPresentImages(std::move(images), nullptr); }
uint32_t Renderer::waitForFrameSlot() { return impl_->waitForFrameSlot(); }
void Renderer::waitIdle() { impl_->waitIdle(); }
void Renderer::renderFrameInBackground() { impl_->renderFrame(true); }
bool Renderer::finishBackgroundFrame() {
    for (FrameSlot& f : impl_->frames)
        if (!impl_->releaseHeld(f, Impl::HeldRelease::IfFinished)) return false;
    return true;
}

ImageData Renderer::readback() {
    const PlanState& s = *impl_->state;
    if (s.readbacks.size() != 1)
        throw ExecutorError(s.readbacks.empty()
                                ? "no read-back: the plan copies no image to the host (CompileOptions::readbacks)"
                                : "the plan reads back " + std::to_string(s.readbacks.size()) +
                                      " images; name one (readback(name))");
    return readback(s.plan.resources()[s.readbacks[0].resource].name);
}

ImageData Renderer::readback(std::string_view resource) {
    Impl& d = *impl_;
    PlanState& s = *d.state;
    const int32_t index = s.plan.resourceIndex(resource);
    const ReadbackTarget* target = index < 0 ? nullptr : s.readbackOf(uint32_t(index));
    if (!target)
        throw ExecutorError("no read-back of '" + std::string(resource) +
                            "': the plan does not copy it to the host (CompileOptions::readbacks)");
    if (d.lastSlot < 0) throw ExecutorError("no read-back of '" + std::string(resource) + "': " + kNoFrameYet);
    d.waitSlot(d.frames[size_t(d.lastSlot)]);
    const ResourceState& r = s.resources[target->resource];
    return convertPixels(target->perSlot[size_t(d.lastSlot)].mapped, r.width, r.height, r.format, r.desc->name);
}

std::vector<ImageData> Renderer::readImage(const std::string& resource) {
    Impl& d = *impl_;
    d.waitIdle();
    PlanState& s = *d.state;
    if (d.lastSlot < 0) throw ExecutorError("cannot read '" + resource + "': " + kNoFrameYet);
    Plan read;
    try {
        read = planImageRead(s.graph, s.plan, resource);
    } catch (const GraphError& e) {
        throw ExecutorError(e.what());
    }
    const uint32_t index = uint32_t(s.plan.resourceIndex(resource));
    const ResourceState& r = s.resources[index];
    if (d.presents(index))
        throw ExecutorError("cannot read '" + resource + "': it is the presented image, the presentation engine's");
    if (!readsBack(r.format)) throw ExecutorError(notReadBackable(resource, r.format));
    // A transient whose memory a later resource of the frame takes over holds that one's
    // contents after the frame, not its own.
    for (const MemoryPlacement& p : s.plan.memory().placements)
        if (std::find(p.aliases.begin(), p.aliases.end(), index) != p.aliases.end())
            throw ExecutorError("cannot read '" + resource + "': '" + std::string(s.plan.resources()[p.resource].name) +
                                "' takes over its memory later in the frame; export it, or give it \"alias\": false");
    const uint32_t slot = d.lastBinding;
    const uint32_t texel = copyTexelBytes(r.desc->format);
    std::vector<VkBufferImageCopy> copies;
    VkDeviceSize bytes = 0;
    for (uint32_t m = 0; m < r.mips; ++m) {
        VkBufferImageCopy c{};
        c.bufferOffset = bytes;
        c.imageSubresource = {copyAspectOf(r.desc->format), m, 0, r.layers};
        c.imageExtent = {r.mipWidth(m), r.mipHeight(m), 1};
        copies.push_back(c);
        bytes += VkDeviceSize(r.mipWidth(m)) * r.mipHeight(m) * texel * r.layers;
    }
    OwnedBuffer host = d.makeHostBuffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    d.submitAndWait([&](CommandSink& sink) {
        const auto target = [&](uint32_t) { return r.barrierTarget(slot); };  // the plan's one resource
        const PlannedPass& step = read.passes().front();  // an image-read plan is one step
        if (const BarrierBatch before(step.barriers, target, d.state->families()); !before.empty()) sink.barriers(before);
        sink.copyImageToBuffer(r.images[r.copyFor(slot)].image, step.usages[0].layout, host.buffer.get(), copies);
        if (const BarrierBatch after(read.finalBarriers(), target, d.state->families()); !after.empty()) sink.barriers(after);
    });
    std::vector<ImageData> levels;
    for (uint32_t m = 0; m < r.mips; ++m)
        for (uint32_t l = 0; l < r.layers; ++l) {
            const VkDeviceSize layerBytes = VkDeviceSize(r.mipWidth(m)) * r.mipHeight(m) * texel;
            const auto* data = static_cast<const uint8_t*>(host.mapped) + copies[m].bufferOffset + l * layerBytes;
            levels.push_back(convertPixels(data, r.mipWidth(m), r.mipHeight(m), r.format, r.desc->name));
        }
    return levels;
}

void Renderer::resize(uint32_t width, uint32_t height) {
    if (width == 0 || height == 0) throw ExecutorError("output extent must be at least 1x1");
    if (const auto& p = impl_->present; p && (p->images.extent.width != width || p->images.extent.height != height))
        throw ExecutorError("resize to " + std::to_string(width) + "x" + std::to_string(height) +
                            ": the renderer presents, at its present images' extent (" +
                            std::to_string(p->images.extent.width) + "x" +
                            std::to_string(p->images.extent.height) + ")");
    std::optional<CompiledGraph> next;
    try {
        next.emplace(impl_->state->compiled.resized(width, height));
    } catch (const GraphError& e) {
        throw ExecutorError(std::string("resize to ") + std::to_string(width) + "x" + std::to_string(height) + ": " +
                            e.what());
    }
    setGraph(std::move(*next));
}

void Renderer::setGraph(CompiledGraph compiled, ShaderSources shaders) {
    Impl& d = *impl_;
    // A presenting renderer renders at its present images' extent, as its constructor does.
    if (d.present) compiled = d.atPresentExtent(std::move(compiled), d.present->images.extent);
    // Swapchain images of another format or usage than the graph presents: the plan is built
    // with a stand-in for them, and the next frame re-creates the swapchain and binds its new
    // images, as a new renderer's first frame does. A format or usage the surface cannot give
    // fails here.
    const bool awaitsImages = d.needsOtherSwapchainImages(compiled);
    d.waitIdle();
    // Rereading builds with a new compiler, which reads every shader again. When that fails,
    // the old one comes back with the sources the running pipelines were built from, so that
    // later rebuilds (a resize) do not read the broken files.
    std::shared_ptr<ShaderCompiler> previous;
    if (shaders == ShaderSources::Reread)
        previous = std::exchange(d.shaders, std::make_shared<ShaderCompiler>(d.shaders->includeDir(),
                                                                             d.shaders->cacheDir()));
    // The build reads whether to bind the present images; a failure puts it back.
    const bool awaited = d.present && d.present->awaitingImages;
    if (d.present) d.present->awaitingImages = awaitsImages;
    try {
        d.replaceState(d.build(std::move(compiled)));  // throws: the old plan keeps running
    } catch (...) {
        if (previous) d.shaders = std::move(previous);
        if (d.present) d.present->awaitingImages = awaited;
        throw;
    }
}

void Renderer::Impl::replaceState(std::unique_ptr<PlanState> next) {
    // The old state's frames have finished (waitIdle() before the build), and what other
    // renderers use of it, images they import, they hold themselves (SharedImage). Work
    // recorded into the application's command buffers is not fenced: only an idle device
    // is sure to be done with it.
    if (recordedElsewhere) vk::check(vkDeviceWaitIdle(vkd), "vkDeviceWaitIdle");
    state = std::move(next);
    lastSlot = -1;
    timings.clear();  // they name the old plan's passes
    timingsFrame.reset();
    passesRecordedUnsubmitted = false;  // the new state's implementations have recorded nothing
}

std::vector<PassTiming> Renderer::lastTimings() {
    Impl& d = *impl_;
    if (d.lastSlot >= 0) d.waitSlot(d.frames[size_t(d.lastSlot)]);
    return d.timings;
}

const std::vector<PassTiming>& Renderer::completedTimings() const noexcept { return impl_->timings; }

const Plan& Renderer::plan() const noexcept { return impl_->state->plan; }
const GraphDesc& Renderer::graph() const noexcept { return impl_->state->graph; }
const CompiledGraph& Renderer::compiled() const noexcept { return impl_->state->compiled; }
const Plan& Renderer::setupPlan() const noexcept { return impl_->state->setup; }
FrameData& Renderer::frameData() noexcept { return impl_->frameData; }

SharedImage::SharedImage() = default;
SharedImage::~SharedImage() = default;
SharedImage::SharedImage(const SharedImage&) = default;
SharedImage& SharedImage::operator=(const SharedImage&) = default;
const std::string& SharedImage::origin() const noexcept {
    static const std::string none = "nothing";
    return impl_ ? impl_->origin : none;
}

SharedImage Renderer::shareImage(const std::string& resource) const {
    const Impl& d = *impl_;
    const int32_t index = d.state->plan.resourceIndex(resource);
    if (index < 0) throw ExecutorError("shareImage: no resource '" + resource + "' in the current plan");
    const ResourceState& r = d.state->resources[size_t(index)];
    const std::string why = !r.isImage            ? "is a buffer, and only images are shared"
                            : d.presents(uint32_t(index)) ? "is the presented image"
                            : !r.desc->external    ? "is not external: set \"external\": true and `final`"
                            : !r.desc->isExported() ? "is not exported: set `final`"
                            : d.state->plan.resources()[size_t(index)].copies == ResourceCopies::PerFramePresented
                                ? "is the plan's presented image (`final: Present`, compiled headless with "
                                  "CompileOptions::presentReplacement), with a copy per frame in flight"
                            : r.perSlot || r.images.size() != 1 ? "has a copy per frame in flight"
                                                                : "";
    if (!why.empty()) throw ExecutorError("shareImage: '" + resource + "' " + why + " (only an exported external image is shared)");
    for (const FrameSlot& f : d.frames)
        if (f.held)
            throw ExecutorError("shareImage: '" + resource + "': the background frame that writes it is not "
                                "finished (call finishBackgroundFrame() until it returns true)");
    auto impl = std::make_shared<SharedImage::Impl>(d.dev);
    impl->storage = r.images[0].storage;
    impl->device = d.vkd;
    impl->format = r.format;
    impl->width = r.width;
    impl->height = r.height;
    impl->mips = r.mips;
    impl->layers = r.layers;
    impl->usage = r.imageUsage;
    impl->layout = d.state->plan.resources()[size_t(index)].finalLayout;
    impl->origin = "graph '" + d.state->graph.name + "', resource '" + resource + "'";
    SharedImage shared;
    shared.impl_ = std::move(impl);
    return shared;
}

void Renderer::importImage(const std::string& resource, SharedImage image) {
    Impl& d = *impl_;
    const ResourceDesc* desc = d.state->graph.findResource(resource);
    if (!desc) throw ExecutorError("importImage: no resource '" + resource + "' in the graph");
    if (!desc->external || !desc->isImage())
        throw ExecutorError("importImage: '" + resource + "' is not an external image");
    if (!image.impl_) throw ExecutorError("importImage: '" + resource + "': the SharedImage is empty");
    // A resource the plan culled is imported when a rebuild brings it back; what the plan
    // would say of it (usages, layout, sharing) is checked then. So is one of a renderer whose
    // swapchain was destroyed, or re-created by another renderer: its passes' framebuffers
    // would be made again from the views of the destroyed images (a use after free); the plan
    // state for the next swapchain, or the next frame's new images, takes it.
    if (const int32_t index = d.state->plan.resourceIndex(resource);
        index >= 0 && !d.presentSwapchainDestroyed() && !d.presentImagesRecreatedElsewhere())
        d.swapImport(*d.state, static_cast<size_t>(index), image);
    else
        d.checkImportShape(*desc, d.state->outputWidth(), d.state->outputHeight(), image);
    d.imports[resource] = std::move(image);
    // Pixels waiting to ride with the next frame would be copied into the producer's image.
    std::erase_if(d.pendingSetups, [&](const Impl::PendingSetup& p) { return p.resource == resource; });
}

void Renderer::forgetImport(const std::string& resource) {
    if (impl_->imports.erase(resource) == 0)
        throw ExecutorError("forgetImport: '" + resource + "' has no imported image");
}

void Renderer::forgetExternalImage(const std::string& resource) {
    if (impl_->uploads.erase(resource) == 0)
        throw ExecutorError("forgetExternalImage: '" + resource + "' has no pixels from setExternalImage()");
}

namespace {

/// Pixels for an imported image would write the producer's image, which this renderer only
/// reads (they did nothing, or were copied into it with the next frame).
std::string importedPixelsProblem(const std::string& resource) {
    return "'" + resource + "' is an imported image (importImage()), which this renderer only reads: its pixels are "
           "its producer's (forgetImport() and a rebuild give it an image of its own again)";
}

}  // namespace

void Renderer::setExternalImage(const std::string& resource, ImageData pixels) {
    Impl& d = *impl_;
    if (const auto problem = Impl::externalPixelsProblem(*d.state, resource, pixels))
        throw ExecutorError("setExternalImage: " + *problem);
    if (d.imports.count(resource)) throw ExecutorError("setExternalImage: " + importedPixelsProblem(resource));
    auto previous = d.uploads;
    d.uploads[resource] = std::move(pixels);
    try {
        // Re-import the externals into the images the plan already has: rebuilding the plan
        // would compile every pipeline again for nothing.
        d.waitIdle();
        d.runSetup(*d.state);
        d.lastSlot = -1;
    } catch (...) {
        d.uploads = std::move(previous);
        throw;
    }
}

void Renderer::updateExternalImage(const std::string& resource, ImageData pixels, UploadTiming timing) {
    Impl& d = *impl_;
    if (const auto problem = Impl::externalPixelsProblem(*d.state, resource, pixels))
        throw ExecutorError("updateExternalImage: " + *problem);
    if (d.imports.count(resource)) throw ExecutorError("updateExternalImage: " + importedPixelsProblem(resource));
    const auto it = d.uploads.find(resource);
    if (it == d.uploads.end())
        throw ExecutorError("updateExternalImage: '" + resource + "' has no pixels yet (setExternalImage first)");
    ImageData previous = std::exchange(it->second, std::move(pixels));
    try {
        // A copy that rides with the next frame is ordered after the frames before by its
        // barriers; runSetup waits for them when it cannot ride.
        if (timing == UploadTiming::Now) d.waitIdle();
        d.runSetup(*d.state, resource, timing == UploadTiming::WithNextFrame);
    } catch (...) {
        it->second = std::move(previous);
        throw;
    }
}

namespace {

/// The plan state's resource `name`, for `call`'s messages.
const ResourceState& stagedResource(const PlanState& s, const std::string& name, const char* call) {
    const int index = s.plan.resourceIndex(name);
    if (index < 0) throw ExecutorError(std::string(call) + ": no resource '" + name + "' in the plan");
    return s.resources[size_t(index)];
}

VkDeviceSize stagedBytes(const ResourceState& r) {
    return r.isImage ? uploadBytes(r.desc->format, r.width, r.height, r.layers) : r.size;
}

}  // namespace

VkDeviceSize Renderer::stagingBytes(const std::string& resource) const {
    return stagedBytes(stagedResource(*impl_->state, resource, "stagingBytes"));
}

void Renderer::stageUpload(const std::string& resource, std::shared_ptr<const StagingBuffer> pixels) {
    Impl& d = *impl_;
    const ResourceState& r = stagedResource(*d.state, resource, "stageUpload");
    if (!pixels) throw ExecutorError("stageUpload: no staging buffer for '" + resource + "'");
    if (pixels->device() != d.vkd)
        throw ExecutorError("stageUpload: '" + resource + "': the staging buffer belongs to another device");
    // Nothing else copies staged pixels: without an UploadPass they would be dropped unread.
    if (!r.uploaded)
        throw ExecutorError("stageUpload: no UploadPass of the plan writes '" + resource +
                            "' (culled, or the resource is filled otherwise): nothing would copy the pixels");
    const VkDeviceSize bytes = stagedBytes(r);
    if (pixels->size() != bytes) {
        const std::string shape = r.isImage ? std::to_string(r.width) + "x" + std::to_string(r.height) + ", " +
                                                  std::to_string(r.layers) + " layer(s) of " +
                                                  std::string(r.desc->format.name)
                                            : "a buffer";
        throw ExecutorError("stageUpload: '" + resource + "' takes " + std::to_string(bytes) + " bytes (" + shape +
                            "), the staging buffer holds " + std::to_string(pixels->size()));
    }
    d.staged[resource] = std::move(pixels);
}

void Renderer::reloadShaders() { setGraph(impl_->state->compiled, ShaderSources::Reread); }
bool Renderer::shadersChangedOnDisk() const { return impl_->shaders->keptFilesChanged(); }
uint64_t Renderer::frameCount() const noexcept { return impl_->frameIndex; }
std::filesystem::path Renderer::shaderDir() const { return impl_->shaders->includeDir(); }
std::shared_ptr<ShaderCompiler> Renderer::shaderCompiler() const { return impl_->shaders; }
const PassLibrary* Renderer::passes() const noexcept { return impl_->options.passes; }

void RendererAccess::recordInto(Renderer& renderer, VkCommandBuffer cmd, uint32_t slot) {
    Renderer::Impl& d = *renderer.impl_;
    if (slot >= d.frames.size() * d.state->presentImages) throw ExecutorError("frame slot out of range");
    if (d.state->plan.submits().size() > 1)
        throw ExecutorError("the plan runs on several queues: each of its submits needs a command buffer of its own");
    d.recordedElsewhere = true;
    d.recordFrame(cmd, slot, nullptr);
}

std::optional<uint64_t> RendererAccess::timingsFrame(const Renderer& renderer) {
    return renderer.impl_->timingsFrame;
}

void RendererAccess::editSetupPlans(Renderer& renderer, std::function<void(Plan&)> edit) {
    renderer.impl_->setupPlanEdit = std::move(edit);
}

void RendererAccess::editSampledImagePlans(Renderer& renderer, std::function<void(Plan&)> edit) {
    renderer.impl_->sampledImagePlanEdit = std::move(edit);
}

void RendererAccess::overrideAcquireWait(Renderer& renderer, std::optional<VkPipelineStageFlags2> stages) {
    renderer.impl_->acquireWaitOverride = stages;
}

void RendererAccess::overrideRenderCompleteSignal(Renderer& renderer, std::optional<VkPipelineStageFlags2> stages) {
    renderer.impl_->signalOverride = stages;
}

HandFrame RendererAccess::handFrame(Renderer& renderer, uint32_t slot) {
    Renderer::Impl& d = *renderer.impl_;
    PlanState& s = *d.state;
    if (slot >= d.frames.size() * s.presentImages) throw ExecutorError("frame slot out of range");
    d.recordedElsewhere = true;
    HandFrame f;
    for (PassState& ps : s.passes) {
        if (ps.kind != StepKind::Pass)
            throw ExecutorError(passError(*ps.pass, "", "hand recording covers the passes' recording code only"));
        const PassSlot& sl = ps.slots[slot];
        HandPass h;
        h.imageBarriers = sl.before.images();
        h.bufferBarriers = sl.before.buffers();
        h.memoryBarriers = sl.before.memory();
        if (ps.attachments.any()) {
            h.renderPass = ps.renderPass.get();
            h.framebuffer = sl.framebuffer.get();
            h.extent = sl.extent;
            h.clearValues = ps.clearValues;
        }
        h.implementation = ps.implementation.get();
        f.passes.push_back(std::move(h));
    }
    f.finalImageBarriers = s.finals[slot].images();
    f.finalBufferBarriers = s.finals[slot].buffers();
    f.finalMemoryBarriers = s.finals[slot].memory();
    return f;
}

}  // namespace skygraph
