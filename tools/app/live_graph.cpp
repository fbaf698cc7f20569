// `skygraph view`'s inputs and renderer, rebuilt on a change.
#include "live_graph.hpp"

#include "environment_bake.hpp"
#include "equirect_resample.hpp"

#include "printable_name.hpp"
#include "procedural_environment.hpp"

#include "shipped_names.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/device.hpp>
#include <skygraph/image_data.hpp>
#include <skygraph/pass.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <exception>
#include <utility>

namespace skygraph::app {
namespace {

/// inputs.graph compiled with `co` (whose memory model is the device's): a transient the
/// device cannot hold is named where its size comes from (throwCapacityError), one it cannot
/// make at its declaration.
CompiledGraph compileForDevice(const FrameInputs& inputs, const CompileOptions& co) {
    try {
        return CompiledGraph(inputs.graph, co);
    } catch (const DeviceCapacityError& e) {
        throwCapacityError(inputs, co, e);
    } catch (const UnsupportedResourceError& e) {  // a format the device cannot make as the plan uses it
        throwAtDeclaration(inputs.graph, e);
    }
}

/// What the overlay edits survives a rebuild; the rest (objects, the environment) comes from
/// the reloaded files.
void keepViewSettings(const Scene& edited, Scene& loaded) {
    loaded.camera = edited.camera;
    loaded.exposureEv = edited.exposureEv;
    loaded.tonemapper = edited.tonemapper;
    loaded.debugView = edited.debugView;
    if (edited.environment && loaded.environment) loaded.environment->rotationDeg = edited.environment->rotationDeg;
    if (edited.environment && loaded.environment && edited.environment->procedural && loaded.environment->procedural)
        loaded.environment->sunDirection = edited.environment->sunDirection;
}

}  // namespace

struct LiveGraph::Built {
    FrameEnvironment environment;  // outlives the renderer that imports its products
    /// The shader sources of the last bake built: environment.renderer's, or, when this build
    /// bakes nothing (a checkbox dropped every product), those of the bake before it, so that
    /// the bake a later rebuild brings back builds from them as a rebuild's bake does.
    std::shared_ptr<ShaderCompiler> bakeShaders;
    std::unique_ptr<Renderer> renderer;
    UploadPassPixels uploads;  // what the graph's UploadPasses copy, every frame
    std::optional<Scene> scene;
    uint32_t sequenceFrame = 0;  // the frame of the scene's sequence the environment was baked from
};

LiveGraph::LiveGraph(Device& device, RenderOptions options, uint32_t width, uint32_t height, bool overlay)
    : device_(device), options_(std::move(options)), width_(width), height_(height), overlay_(overlay) {
    built_ = build(options_, Renderer::ShaderSources::Reread, Renderer::ShaderSources::Reread);
    renderer_ = built_->renderer.get();
    scene_ = built_->scene;
    if (!options_.graph.empty()) graphWatcher_.emplace(options_.graph);
    if (!options_.scene.empty()) sceneWatcher_.emplace(options_.scene);
    environmentGraphFile_ = environmentGraphFile(options_);
    if (!environmentGraphFile_.empty()) environmentGraphWatcher_.emplace(environmentGraphFile_);
    // No graph file: HotReloader watches the shaders alone.
    shaderWatcher_ = std::make_unique<HotReloader>(*renderer_, std::filesystem::path());
    startSequence();
}

void LiveGraph::forgetPlayback() {
    player_.reset();
    sequenceBaking_ = false;
    playbackOrigin_.reset();
    fadeStarting_ = false;
    fadeStart_.reset();
}

void LiveGraph::stopSequence() {
    forgetPlayback();
    // No fade is left half way: the sky shows the cube swapped in last.
    if (!environmentShown_.empty() && renderer_->plan().resourceIndex(shipped::kEnvironmentPrevious) >= 0) {
        renderer_->frameData().set(SkyFade{1.0});
        renderer_->importImage(std::string(shipped::kEnvironmentPrevious), environmentShown_);
    }
}

void LiveGraph::startSequence(const std::optional<Playback>& from) {
    forgetPlayback();
    const FrameEnvironment& built = built_->environment;
    environmentShown_ = built.products.contains(shipped::kEnvironment)
                            ? built.renderer->shareImage(std::string(shipped::kEnvironment))
                            : SharedImage();
    const Scene* scene = built_->scene ? &*built_->scene : nullptr;
    if (!scene || !scene->environment || !scene->environment->sequence || scene->environment->sequence->count < 2)
        return;
    const ResourceDesc* equirect = renderer_->graph().findResource(shipped::kEquirect);
    if (!built_->environment.graph || !equirect) {
        spdlog::warn("environment sequence: the graph bakes no environment from an equirect; the sky shows the first frame");
        return;
    }
    const auto extent = equirect->extent.resolve(width_, height_);
    // The stream stages its frames for the bake's upload, unless the frame samples the
    // equirect itself and needs the pixels on the host too (rebake()).
    const bool staged = renderer_->plan().resourceIndex(shipped::kEquirect) < 0;
    const EnvironmentSequence& sequence = *scene->environment->sequence;
    const bool goesOn = from && from->sequence == sequence &&
                        built_->sequenceFrame == uint32_t(from->position.tick % sequence.count);
    player_ = std::make_unique<SequencePlayer>(sequence, extent[0], extent[1], staged ? &device_ : nullptr,
                                               goesOn ? std::optional(from->position) : std::nullopt);
    if (goesOn) playbackOrigin_ = from->origin;
}

void LiveGraph::playSequence(double clockSeconds) {
    if (!player_) return;
    // Playback starts at the first call after the player was made (a rebuild makes a new one).
    if (!playbackOrigin_) playbackOrigin_ = clockSeconds;
    const double seconds = clockSeconds - *playbackOrigin_;
    if (sequenceBaking_ && !rebaking()) {  // poll() swapped it in
        player_->swappedIn(seconds);
        sequenceBaking_ = false;
    }
    if (std::exchange(fadeStarting_, false)) fadeStart_ = seconds;
    if (fadeStart_) {
        const double fade = std::min((seconds - *fadeStart_) * player_->fps(), 1.0);
        renderer_->frameData().set(SkyFade{fade});
        if (fade >= 1.0) fadeStart_.reset();
    }
    if (!canRebake()) return;
    std::optional<SequenceFrame> frame = player_->frameToBake(seconds);
    if (!frame) return;
    if (!frame->error.empty()) {
        spdlog::warn("environment sequence: {}; the sky holds the last frame", frame->error);
        return;
    }
    try {
        if (frame->staged) {
            const auto extent = renderer_->graph().findResource(shipped::kEquirect)->extent.resolve(width_, height_);
            sequenceBaking_ = baker(extent[0], extent[1]).start(std::move(frame->staged));
        } else {
            sequenceBaking_ = rebake(std::move(frame->pixels), {});
        }
        if (!sequenceBaking_) player_->bakeFailed();
    } catch (const std::exception& e) {
        player_->bakeFailed();
        spdlog::warn("environment sequence: {}: {}; the sky holds the last frame", printableName(frame->file), e.what());
    }
}

LiveGraph::~LiveGraph() {
    if (renderer_) renderer_->waitIdle();
}

std::unique_ptr<LiveGraph::Built> LiveGraph::build(const RenderOptions& options, Renderer::ShaderSources shaders,
                                                   Renderer::ShaderSources bakeShaders) const {
    auto b = std::make_unique<Built>();
    FrameInputs inputs = loadFrameInputs(options);
    const std::string ui(shipped::kOverlayFeature);
    const auto& declared = inputs.graph.features;
    const auto isDeclared = [&](const std::string& name) {
        return std::any_of(declared.begin(), declared.end(), [&](const FeatureDecl& f) { return f.name == name; });
    };
    // A feature set since the start (the overlay's checkboxes, F1) that a saved graph no longer
    // declares is dropped: as an unknown feature it would refuse every later save. The first
    // build keeps them, so that a wrong --feature is an error.
    if (renderer_)
        std::erase_if(inputs.compile.features, [&](const auto& feature) {
            if (isDeclared(feature.first)) return false;
            spdlog::info("feature '{}' is not declared by the graph any more: dropped", feature.first);
            return true;
        });
    if (!options.features.contains(ui) && isDeclared(ui)) inputs.compile.features[ui] = overlay_;
    if (inputs.scene && scene_) keepViewSettings(*scene_, *inputs.scene);
    b->scene = inputs.scene;
    b->sequenceFrame = inputs.sequenceFrame;
    CompileOptions co = inputs.compile;  // presented: the Present resource stays Present
    co.outputWidth = width_;
    co.outputHeight = height_;
    co.memory = device_.memoryModel();  // what the renderer compiles with: it would compile again
    CompiledGraph compiled = compileForDevice(inputs, co);
    for (const auto& c : compiled.plan().culled()) spdlog::info("culled {}: {}", c.name, c.reason);
    const std::shared_ptr<ShaderCompiler> lastBake = built_ ? built_->bakeShaders : nullptr;
    b->environment = bakeFrameEnvironment(device_, compiled.plan(), inputs, options,
                                          bakeShaders == Renderer::ShaderSources::Cached ? lastBake : nullptr);
    b->bakeShaders = b->environment.renderer ? b->environment.renderer->shaderCompiler() : lastBake;
    RendererOptions ro;
    ro.framesInFlight = options.framesInFlight;
    ro.passes = inputs.passes;
    ro.presentTo = swapchain_;
    if (shaders == Renderer::ShaderSources::Cached && renderer_) ro.shaderCompiler = renderer_->shaderCompiler();
    try {  // the renderer checks every resource, the externals and exported ones too
        b->renderer = std::make_unique<Renderer>(device_, std::move(compiled), ro);
    } catch (const DeviceCapacityError& e) {
        throwCapacityError(inputs, co, e);
    } catch (const UnsupportedResourceError& e) {  // e.g. a format the window cannot present
        throwAtDeclaration(inputs.graph, e);
    }
    b->uploads = UploadPassPixels(device_, *b->renderer, inputs.environment);
    attachFrameInputs(*b->renderer, inputs, b->environment);
    return b;
}

bool LiveGraph::rebuild(RenderOptions options, Renderer::ShaderSources shaders, Renderer::ShaderSources bakeShaders) {
    // The running renderer follows the window; the new one starts at its size.
    width_ = renderer_->compiled().outputWidth();
    height_ = renderer_->compiled().outputHeight();
    // An environment file still decoding is built in, unless this rebuild is for another one;
    // one that cannot be read is reported as finishEnvironmentLoad() would, and left out.
    std::string loadError;
    if (load_ && options.environmentFile == options_.environmentFile) {
        try {
            (void)load_->result.get();
            options.environmentFile = load_->next.environmentFile;
        } catch (const std::exception& e) {
            loadError = e.what();
            spdlog::warn("{}", loadError);
        }
        load_.reset();
    }
    // Playback goes on through the rebuild, which bakes the environment from the frame on
    // screen (or the one being baked) instead of the sequence's first.
    std::optional<Playback> playing;
    if (player_) playing = Playback{player_->stream().sequence(), player_->position(), playbackOrigin_};
    std::unique_ptr<Built> next;
    try {
        RenderOptions building = options;
        if (playing)
            building.sequenceFrame = {playing->sequence, uint32_t(playing->position.tick % playing->sequence.count)};
        next = build(building, shaders, bakeShaders);
    } catch (const std::exception& e) {
        error_ = loadError.empty() ? e.what() : loadError + "\n" + e.what();
        spdlog::warn("{}", e.what());
        return false;
    }
    renderer_->waitIdle();
    // A bake built from the sources of one that was not running may be behind an edit made
    // meanwhile, which no bake saw: the next poll looks, as it does after an edit.
    if (!built_->environment.renderer && next->environment.renderer && built_->bakeShaders &&
        bakeShaders == Renderer::ShaderSources::Cached)
        checkBakeShaders_ = true;
    built_ = std::move(next);  // the old renderer is gone before the new one records
    baker_.reset();            // the new build baked its own environment
    rebakeEquirect_.reset();
    load_.reset();             // a file for another environment, still decoding (waits for it)
    renderer_ = built_->renderer.get();
    // The watcher's record of the shaders carries over: an edit saved while this was built, or
    // one a failed reload left pending, is still applied.
    shaderWatcher_->follow(*renderer_);
    if (built_->scene) scene_ = built_->scene;
    options_ = std::move(options);
    // Built from the graph file as it is now. A saved scene still pending is not applied as a
    // save is (its view settings win over the overlay's): rebuildAfterSave does. Shaders from
    // the running renderer's sources say nothing of one broken on disk: its message stays.
    error_ = loadError;
    if (shaders == Renderer::ShaderSources::Reread) shaderError_.clear();
    if (bakeShaders == Renderer::ShaderSources::Reread) bakeShaderError_.clear();  // baked from the files on disk
    graphSavePending_ = false;
    ++reloads_;
    startSequence(playing);
    return true;
}

PresentStatus LiveGraph::renderFrame(Swapchain& swapchain) {
    built_->uploads.stageFor(*renderer_);
    try {  // the first frame into a swapchain checks the presented image against its images
        return renderer_->renderFrame(swapchain);
    } catch (const UnsupportedResourceError& e) {  // e.g. a fixed extent that is not the window's
        throwAtDeclaration(renderer_->graph(), e);
    }
}

void LiveGraph::sceneChanged() {
    if (scene_) renderer_->frameData().set(*scene_);
}

std::vector<std::pair<std::string, bool>> LiveGraph::features() const {
    std::vector<std::pair<std::string, bool>> out;
    for (const FeatureDecl& f : renderer_->graph().features) out.emplace_back(f.name, feature(f.name));
    return out;
}

bool LiveGraph::declares(std::string_view name) const {
    const auto& declared = renderer_->graph().features;
    return std::any_of(declared.begin(), declared.end(), [&](const FeatureDecl& f) { return f.name == name; });
}

bool LiveGraph::sceneReplaced() noexcept { return std::exchange(sceneReplaced_, false); }

std::string LiveGraph::error() const {
    std::string all;
    for (const std::string* message : {&error_, &shaderError_, &bakeShaderError_})
        if (!message->empty()) all += (all.empty() ? "" : "\n") + *message;
    return all;
}

bool LiveGraph::feature(std::string_view name) const {
    const FeatureValues& on = renderer_->plan().features();
    const auto it = on.find(std::string(name));
    return it != on.end() && it->second;
}

bool LiveGraph::setFeature(const std::string& name, bool on) {
    RenderOptions next = options_;
    next.features[name] = on;
    return rebuild(std::move(next), Renderer::ShaderSources::Cached);
}

bool LiveGraph::setEnvironmentFile(const std::filesystem::path& file) {
    RenderOptions next = options_;
    next.environmentFile = file;
    // The procedural sky is drawn by a skybox of its own (the scene's feature environment_file):
    // a file in its place needs the plan that draws the file, not only the file's lighting.
    const bool proceduralSky = scene_ && scene_->environment && scene_->environment->procedural;
    if (!proceduralSky && rebakeInPlace(file, next)) return true;  // its message, if any, once decoded
    return rebuild(std::move(next), Renderer::ShaderSources::Cached);
}

bool LiveGraph::rebakeInPlace(const std::filesystem::path& file, RenderOptions next) {
    if (file.empty() || !canRebake()) return false;
    // The running image's size is the frame graph's `equirect` (loadFrameInputs sets it).
    const auto extent = renderer_->graph().findResource(shipped::kEquirect)->extent.resolve(width_, height_);
    const bool keepPixels = renderer_->plan().resourceIndex(shipped::kEquirect) >= 0;
    std::shared_ptr<StagingBuffer> reuse = loadStaging_.use_count() == 1 ? loadStaging_ : nullptr;
    auto decode = [file, extent, keepPixels, reuse, &device = device_]() mutable {
        HdrImage pixels = loadEnvironmentImage(file);  // throws: reported once the load is finished
        if (pixels.width != extent[0] || pixels.height != extent[1]) {
            spdlog::info("environment: {} is {}x{}; resampled to the running {}x{} for a bake beside the frames",
                         printableName(file.string()), pixels.width, pixels.height, extent[0], extent[1]);
            pixels = resampleEquirect(pixels, extent[0], extent[1]);
        }
        const size_t bytes = pixels.rgba.size() * sizeof(float);
        LoadedEnvironment out;
        out.staged = reuse && reuse->size() == bytes ? std::move(reuse) : StagingBuffer::create(device, bytes);
        std::memcpy(out.staged->bytes().data(), pixels.rgba.data(), bytes);
        if (keepPixels) out.pixels = std::move(pixels);
        return out;
    };
    load_ = EnvironmentLoad{file, std::move(next), std::async(std::launch::async, std::move(decode))};
    return true;
}

void LiveGraph::finishEnvironmentLoad() {
    if (!load_ || load_->result.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    EnvironmentLoad load = std::move(*load_);
    load_.reset();
    try {
        LoadedEnvironment loaded = load.result.get();  // throws what the decoding threw
        stopSequence();  // the file replaces it
        const auto extent = renderer_->graph().findResource(shipped::kEquirect)->extent.resolve(width_, height_);
        loadStaging_ = loaded.staged;
        if (loaded.pixels) rebakeEquirect_ = std::move(loaded.pixels);
        spdlog::info("environment: re-baking {} beside the frames", printableName(load.file.string()));
        if (!baker(extent[0], extent[1]).start(std::move(loaded.staged))) {
            rebuild(std::move(load.next), Renderer::ShaderSources::Cached);
            return;
        }
        options_ = std::move(load.next);
        // A save that did not build is still not built: its message stays.
        if (!graphSavePending_ && !sceneSavePending_) error_.clear();
    } catch (const std::exception& e) {
        error_ = e.what();
        spdlog::warn("{}", error_);
    }
}

bool LiveGraph::canRebake() const {
    return built_->environment.graph && renderer_->graph().findResource(shipped::kEquirect) && !rebaking();
}

bool LiveGraph::rebake(HdrImage pixels, const std::string& what) {
    // The running image's size is the frame graph's `equirect` (loadFrameInputs sets it).
    const auto extent = renderer_->graph().findResource(shipped::kEquirect)->extent.resolve(width_, height_);
    if (pixels.width != extent[0] || pixels.height != extent[1]) {  // never for a sequence's frames: the stream resamples
        // The running equirect and products keep their sizes, so the bake stays beside the
        // frames; a rebuild (a graph or scene edit) bakes the file at its own size.
        spdlog::info("environment: {} is {}x{}; resampled to the running {}x{} for a bake beside the frames", what,
                     pixels.width, pixels.height, extent[0], extent[1]);
        pixels = resampleEquirect(pixels, extent[0], extent[1]);
    }
    EnvironmentBaker& bake = baker(pixels.width, pixels.height);
    if (renderer_->plan().resourceIndex(shipped::kEquirect) >= 0) rebakeEquirect_ = pixels;
    if (!what.empty()) spdlog::info("environment: re-baking {} beside the frames", what);
    return bake.start(pixels);
}

EnvironmentBaker& LiveGraph::baker(uint32_t width, uint32_t height) {
    if (baker_) return *baker_;
    // A sky that fades samples two swaps' products: a third renderer bakes meanwhile.
    const bool fades = renderer_->plan().resourceIndex(shipped::kEnvironmentPrevious) >= 0;
    baker_ = std::make_unique<EnvironmentBaker>(device_, *built_->environment.graph, width, height,
                                                built_->environment.products,
                                                options_.passes ? options_.passes : &PassLibrary::genericOnly(), true,
                                                fades ? 3 : 2, built_->environment.renderer->shaderCompiler());
    return *baker_;
}

bool LiveGraph::setSunDirection(const Vec3& sun) {
    if (!scene_ || !scene_->environment || !scene_->environment->procedural) return false;
    scene_->environment->sunDirection = sun;
    options_.sunDirection = sun;  // what a later rebuild bakes
    sceneChanged();               // the skybox draws the new sun at once
    pendingSun_ = sun;            // the lighting follows once a bake is free (poll)
    startPendingSunBake();
    return true;
}

void LiveGraph::startPendingSunBake() {
    if (!pendingSun_ || !canRebake()) return;
    try {
        // A bake that cannot start beside the frames: a rebuild bakes the sun.
        if (!rebake(proceduralSkyEquirect(*pendingSun_), "the procedural sky"))
            rebuild(options_, Renderer::ShaderSources::Cached);
        pendingSun_.reset();
    } catch (const std::exception& e) {
        error_ = e.what();
        spdlog::warn("{}", error_);
        pendingSun_.reset();
    }
}

void LiveGraph::swapRebake() {
    const SharedImage shown = environmentShown_;
    if (!baker_ || !baker_->swapInWhenFinished(*renderer_)) return;
    environmentShown_ = baker_->swappedIn(std::string(shipped::kEnvironment));
    // The fade's source is the cube shown until now, never an older one: the baker reuses the
    // renderer swapped in before it. Another file than a sequence's frame is not faded to.
    if (renderer_->plan().resourceIndex(shipped::kEnvironmentPrevious) >= 0) {
        const bool fade = sequenceBaking_ && !shown.empty();
        renderer_->importImage(std::string(shipped::kEnvironmentPrevious), fade ? shown : environmentShown_);
        renderer_->frameData().set(SkyFade{fade ? 0.0 : 1.0});
        fadeStarting_ = fade;
        fadeStart_.reset();
    }
    // The frame's own equirect (a skybox that samples it): uploaded at the swap, so that the
    // sky and the lighting change together; this waits for the frames in flight.
    if (rebakeEquirect_)
        renderer_->updateExternalImage(std::string(shipped::kEquirect), toImageData(*std::exchange(rebakeEquirect_, std::nullopt)));
    if (!sequenceBaking_) ++reloads_;  // a sequence's frames are playback, not reloads
}

void LiveGraph::rebuildAfterSave(bool graphSaved, bool sceneSaved, std::filesystem::file_time_type saved,
                                 bool reportLatency) {
    std::optional<Scene> edited;
    if (sceneSaved) {  // the saved scene wins over the overlay, its sun included
        edited = std::exchange(scene_, std::nullopt);
        options_.sunDirection.reset();
        pendingSun_.reset();
    }
    const auto noticed = std::filesystem::file_time_type::clock::now();
    if (rebuild(options_, Renderer::ShaderSources::Reread)) {
        lastReload_ = {saved, noticed, std::filesystem::file_time_type::clock::now(), reportLatency};
        sceneReplaced_ = sceneReplaced_ || sceneSaved;
        graphSavePending_ = sceneSavePending_ = false;
        return;
    }
    graphSavePending_ = graphSavePending_ || graphSaved;
    sceneSavePending_ = sceneSavePending_ || sceneSaved;
    if (edited) scene_ = std::move(edited);
}

bool LiveGraph::poll() {
    finishEnvironmentLoad();
    swapRebake();
    startPendingSunBake();
    // The environment graph is part of the frame's: a save of it builds everything again too.
    const bool environmentGraphSaved = environmentGraphWatcher_ && environmentGraphWatcher_->changed();
    const bool graphSaved = (graphWatcher_ && graphWatcher_->changed()) || environmentGraphSaved;
    const bool sceneSaved = sceneWatcher_ && sceneWatcher_->changed();
    if (graphSaved || sceneSaved) {
        std::error_code ec;
        const auto saved = std::filesystem::last_write_time(
            environmentGraphSaved ? environmentGraphFile_ : graphSaved ? options_.graph : options_.scene, ec);
        // A save still pending (its build failed) is part of this one's.
        rebuildAfterSave(graphSaved || graphSavePending_, sceneSaved || sceneSavePending_, saved, !ec);
        return true;
    }
    const HotReloader::Result shaders = shaderWatcher_->poll();
    if ((graphSavePending_ || sceneSavePending_) && shaders != HotReloader::Result::Unchanged) {
        // A save whose build failed (a shader its plan compiles did not) is built again after a
        // shader edit: the reload just done rebuilt the pipelines of the plan from before it.
        // The time of that edit is not known, so no latency is reported for this rebuild.
        shaderError_ = shaders == HotReloader::Result::Failed ? shaderWatcher_->lastError() : std::string();
        rebuildAfterSave(graphSavePending_, sceneSavePending_, {}, false);
        return true;
    }
    // The environment was baked once, by a renderer of its own that the watcher (which sees
    // every edit in the shader directory) does not reload: an edit to a shader that bake was
    // built from bakes it again, in a rebuild that keeps everything else; so does one made
    // while no bake ran, once a bake is back (checkBakeShaders_).
    // A failed bake keeps its message apart, to go when the edit is undone.
    const Renderer* bake = built_->environment.renderer.get();
    const bool bakeMayBeBehind = std::exchange(checkBakeShaders_, false);
    if ((shaders != HotReloader::Result::Unchanged || bakeMayBeBehind) && bake) {
        if (bake->shadersChangedOnDisk()) {
            if (shaders != HotReloader::Result::Unchanged)
                shaderError_ = shaders == HotReloader::Result::Failed ? shaderWatcher_->lastError() : std::string();
            std::string before = error_;
            if (!rebuild(options_, Renderer::ShaderSources::Cached, Renderer::ShaderSources::Reread))
                bakeShaderError_ = std::exchange(error_, std::move(before));
            return true;
        }
        bakeShaderError_.clear();
    }
    switch (shaders) {
        case HotReloader::Result::Unchanged: return false;
        case HotReloader::Result::Reloaded:
            shaderError_.clear();
            ++reloads_;
            return true;
        case HotReloader::Result::Failed:
            shaderError_ = shaderWatcher_->lastError();
            return true;
    }
    return false;
}

std::string LiveGraph::presentedResource() const {
    const auto presentations = renderer_->plan().presentations();
    return presentations.empty() ? std::string()
                                 : std::string(renderer_->plan().resources()[presentations[0].resource].name);
}

bool LiveGraph::beginScreenshot() {
    const std::string target = presentedResource();
    if (target.empty()) {
        error_ = "screenshot: the plan presents no image";
        return false;
    }
    CompileOptions co = renderer_->compiled().options();
    co.readbacks.insert(target);
    try {
        renderer_->setGraph(CompiledGraph(renderer_->graph(), co));
    } catch (const std::exception& e) {
        error_ = std::string("screenshot: ") + e.what();
        spdlog::warn("{}", error_);
        return false;
    }
    return true;
}

bool LiveGraph::finishScreenshot(const std::filesystem::path& png) {
    bool written = false;
    try {
        if (!png.empty()) {
            writePng(png, renderer_->readback());
            spdlog::info("screenshot: {}", printableName(png.string()));
            written = true;
        }
    } catch (const std::exception& e) {
        error_ = std::string("screenshot: ") + e.what();
        spdlog::warn("{}", error_);
    }
    CompileOptions co = renderer_->compiled().options();
    co.readbacks.erase(presentedResource());
    try {
        renderer_->setGraph(CompiledGraph(renderer_->graph(), co));
    } catch (const std::exception& e) {
        error_ = std::string("screenshot: ") + e.what();
        return false;
    }
    return written;
}

}  // namespace skygraph::app
