// `skygraph render`: compile a graph file and render it headless.
#include "render.hpp"

#include "equirect_resample.hpp"

#include "command_exit.hpp"

#include "environment_bake.hpp"
#include "replace_file.hpp"
#include "environment_graph.hpp"
#include "file_extension.hpp"
#include "output_file_name.hpp"
#include "printable_name.hpp"
#include "procedural_environment.hpp"
#include "shipped_names.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/format.hpp>
#include <skygraph/device.hpp>
#include <skygraph/hdr_image.hpp>
#include <skygraph/image_data.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <optional>
#include <iostream>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph::app {
namespace {

using namespace shipped;

/// `message` as a GraphError at `declared`'s declaration in `graph`, or at `graph`'s file
/// when `declared` is null.
[[noreturn]] void throwInGraph(const GraphDesc& graph, const ResourceDesc* declared, std::string message) {
    Diagnostics d;
    d.add({graph.file, declared ? declared->jsonPath() : "", "", "", std::move(message)});
    throw GraphError(std::move(d));
}

/// graphs/ibl.json: RenderOptions::environmentGraphText, else environmentGraphFile().
std::optional<GraphDesc> loadEnvironmentGraph(const RenderOptions& options, const PassRegistry& registry) {
    if (!options.environmentGraphText.empty())
        return parseGraph(options.environmentGraphText, std::string(kBuiltinEnvironmentGraphName), registry);
    const std::filesystem::path file = environmentGraphFile(options);
    std::error_code ec;
    if (file.empty() || (options.environmentGraph.empty() && !std::filesystem::exists(file, ec))) return std::nullopt;
    return loadGraphFile(file, registry);
}

/// The scene's environment file, when the frame has one (not the procedural sky).
const SceneEnvironment* environmentFile(const FrameInputs& inputs) {
    if (!inputs.environment || !inputs.scene || !inputs.scene->environment || inputs.scene->environment->procedural)
        return nullptr;
    return &*inputs.scene->environment;
}

/// `e`, for a resource as large as the environment file, named where the scene names the file.
[[noreturn]] void throwAtEnvironmentFile(const FrameInputs& inputs, const SceneEnvironment& sky,
                                         const DeviceCapacityError& e, std::string_view doing) {
    const std::filesystem::path file = sky.sequence ? sky.sequence->frame(inputs.sequenceFrame) : sky.file;
    Diagnostics d;
    d.add({inputs.scene->file, sky.sequence ? "environment.sequence" : "environment.file", "", "",
           "'" + printableName(file.string()) + "' (" + std::to_string(inputs.environment->width) + "x" +
               std::to_string(inputs.environment->height) + ") is too large for this device" + std::string(doing) +
               ": " + e.what()});
    throw SceneError(std::move(d));
}


/// What the plan samples of the environment pipeline's outputs: the externals it imports
/// (`initial` set) that the environment graph exports under the same name.
std::set<std::string, std::less<>> environmentProducts(const Plan& plan, const GraphDesc& graph,
                                                       const GraphDesc* environmentGraph) {
    std::set<std::string, std::less<>> products;
    std::set<size_t> written;
    for (const PlannedPass& p : plan.passes())
        for (const PlannedUsage& u : p.usages)
            if (writesContents(u.usage.access)) written.insert(u.resource);
    for (size_t i = 0; i < plan.resources().size(); ++i) {
        const PlannedResource& r = plan.resources()[i];
        const ResourceDesc& d = graph.resources[r.decl];
        // What the plan only reads: a graph that writes an external (graphs/ibl.json itself)
        // produces it.
        // The previous environment is the environment's cube, imported by attachFrameInputs.
        if (!d.external || d.name == kEquirect || d.name == kEnvironmentPrevious || written.count(i)) continue;
        const ResourceDesc* produced = environmentGraph ? environmentGraph->findResource(d.name) : nullptr;
        if (produced && produced->isExported()) {
            products.insert(d.name);
        } else if (d.initial == ExternalState::ShaderRead) {
            spdlog::warn("'{}' is imported but no environment graph exports it: it holds a placeholder", d.name);
        }
    }
    return products;
}

/// The environment graph (sized like the frame by the caller), baked once on `equirect`
/// for `products`; the returned renderer owns them (share them with Renderer::shareImage()).
/// `shaders` as for bakeEnvironment().
std::unique_ptr<Renderer> bakeForFrame(Device& device, GraphDesc graph, const HdrImage& equirect,
                                       const std::set<std::string, std::less<>>& products, const PassLibrary* passes,
                                       std::shared_ptr<ShaderCompiler> shaders) {
    EnvironmentBake bake = bakeEnvironment(device, std::move(graph), equirect, products, passes, {}, std::move(shaders));
    for (const auto& c : bake.renderer->plan().culled()) spdlog::info("environment: culled {}: {}", c.name, c.reason);
    for (const auto& t : bake.renderer->lastTimings())
        spdlog::info("environment: pass {:<20} {:8.3f} ms (GPU)", t.pass, t.milliseconds);
    return std::move(bake.renderer);
}

/// The image `render` writes: `readback` if named, else the graph's Present image that a pass
/// of `plan` (compiled without read-backs) uses, so that with several (raster.json's
/// swapchain and swapchain_storage) it is the one the features keep; else none.
std::string outputTarget(const GraphDesc& graph, const Plan& plan, const std::string& readback) {
    if (!readback.empty()) return readback;
    for (const PlannedPass& p : plan.passes())
        for (const PlannedUsage& u : p.usages) {
            const std::string_view name = plan.resources()[u.resource].name;
            const ResourceDesc* r = graph.findResource(name);
            if (r && r->final == ExternalState::Present) return std::string(name);
        }
    return {};
}

/// The resources that passes of `plan` write (an inserted step, a Clear, does not count).
std::set<std::string, std::less<>> writtenByPasses(const Plan& plan) {
    std::set<std::string, std::less<>> written;
    for (const PlannedPass& p : plan.passes())
        if (p.declIndex >= 0)
            for (const PlannedUsage& u : p.usages)
                if (writesContents(u.usage.access)) written.emplace(plan.resources()[u.resource].name);
    return written;
}

/// The images of `written` (writtenByPasses), which a read-back shows the frame's work in, in
/// the order `graph` declares them.
std::string writtenImageNames(const GraphDesc& graph, const std::set<std::string, std::less<>>& written) {
    std::string names;
    for (const ResourceDesc& r : graph.resources)
        if (r.isImage() && written.contains(r.name)) names += (names.empty() ? "" : ", ") + r.name;
    return names;
}

}  // namespace

std::filesystem::path environmentGraphFile(const RenderOptions& options) {
    if (!options.environmentGraphText.empty()) return {};
    if (!options.environmentGraph.empty()) return options.environmentGraph;  // named: its absence is an error
    if (options.graph.empty()) return {};
    return options.graph.parent_path() / kEnvironmentGraphFile;
}

FrameInputs loadFrameInputs(const RenderOptions& options) {
    FrameInputs in;
    in.registry = options.passes ? options.passes->registry() : PassRegistry::withBuiltins();
    // Null: every pass type is recorded as Generic.
    in.passes = options.passes ? options.passes : &PassLibrary::genericOnly();
    in.graph = options.graphText.empty()
                   ? loadGraphFile(options.graph, in.registry)
                   : parseGraph(options.graphText, std::string(kBuiltinFrameGraphName), in.registry);
    GraphDesc& graph = in.graph;
    std::optional<Scene>& scene = in.scene;
    if (!options.sceneText.empty())
        scene = parseScene(options.sceneText, std::string(kBuiltinSceneName), std::filesystem::current_path());
    else if (!options.scene.empty())
        scene = loadSceneFile(options.scene);
    if (scene && options.environmentFile) {
        SceneEnvironment& e = scene->environment ? *scene->environment : scene->environment.emplace();
        e.procedural = options.environmentFile->empty();
        e.file = e.procedural ? std::filesystem::path() : std::filesystem::absolute(*options.environmentFile);
        e.sequence.reset();  // the file replaces the scene's sequence too
    }
    if (scene && scene->environment && scene->environment->procedural && options.sunDirection)
        scene->environment->sunDirection = *options.sunDirection;
    // The environment image is made before compiling: its size is the extent of the graph's
    // `equirect` (data-driven, so the plan's subresources match the image). The procedural
    // sky is rendered to one, so that it lights the scene through the same bake as a file.
    std::optional<HdrImage>& environment = in.environment;
    if (scene && scene->environment) {
        if (scene->environment->procedural) {
            environment = proceduralSkyEquirect(scene->environment->sunDirection);
            spdlog::info("environment: the procedural sky ({}x{})", environment->width, environment->height);
        } else {
            const SceneEnvironment& sky = *scene->environment;
            std::filesystem::path file = sky.file;
            if (sky.sequence && options.sequenceFrame && options.sequenceFrame->sequence == *sky.sequence &&
                options.sequenceFrame->frame > 0 && options.sequenceFrame->frame < sky.sequence->count) {
                // Read again at a rebuild, it may be gone: playback skips a frame it cannot
                // read, and the rebuild does too.
                try {
                    environment = loadEnvironmentImage(sky.sequence->frame(options.sequenceFrame->frame));
                    in.sequenceFrame = options.sequenceFrame->frame;
                    file = sky.sequence->frame(in.sequenceFrame);
                } catch (const ImageError& e) {
                    spdlog::warn("environment sequence: {}; baked from the first frame", e.what());
                }
            }
            try {
                if (!environment) environment = loadEnvironmentImage(file);
            } catch (const ImageError& e) {  // named where the scene names it
                Diagnostics d;
                d.add({scene->file, sky.sequence ? "environment.sequence" : "environment.file", "", "", e.what()});
                throw SceneError(std::move(d));
            }
            spdlog::info("environment: {} ({}x{})", printableName(file.string()), environment->width,
                         environment->height);
        }
        if (!setEquirectExtent(graph, environment->width, environment->height) && !scene->environment->procedural)
            spdlog::warn("graph '{}' has no resource '{}': the environment file is not used", graph.name,
                         kEquirect);
    }
    // No more environment than the view can show: both graphs get the same sizes, so the
    // frame imports exactly what the environment graph exports.
    if (environment && options.fitEnvironmentToView) {
        in.environmentSizes = viewEnvironmentSizes(graph, options.height, scene->camera.fovYDeg, environment->width);
        if (in.environmentSizes) {
            resizeEnvironmentGraph(graph, *in.environmentSizes);
            spdlog::info("environment: cube {}^2, prefiltered {}^2 for a {}-pixel-tall view at {} degrees "
                         "(equirect {} wide)",
                         in.environmentSizes->environment, in.environmentSizes->prefiltered, options.height,
                         scene->camera.fovYDeg, environment->width);
        }
    }
    // A sequence's frames are baked again and again beside the frames: where the sky samples
    // the cube, each is uploaded only as wide as the cube needs (the stream resamples the
    // frames to this size), which bounds the copy, the bakes' memory and their filtering.
    if (environment && in.environmentSizes && scene->environment->sequence &&
        scene->environment->sampling == EnvironmentSampling::Cubemap) {
        const uint32_t width = sequenceEquirectWidth(in.environmentSizes->environment, environment->width);
        if (width < environment->width) {
            spdlog::info("environment: the sequence's frames are baked at {}x{} (from {}x{}) for the {}^2 cube", width,
                         width / 2, environment->width, environment->height, in.environmentSizes->environment);
            *environment = resampleEquirect(*environment, width, width / 2);
            setEquirectExtent(graph, width, width / 2);
        }
    }
    CompileOptions& co = in.compile;
    if (scene) {
        // Only the scene features this graph declares: pathtrace.json has no skybox.
        for (const auto& [name, on] : sceneFeatures(*scene)) {
            const std::string& feature = name;  // clang 14 (CI's sanitizer build) cannot capture bindings
            if (std::any_of(graph.features.begin(), graph.features.end(),
                            [&](const FeatureDecl& f) { return f.name == feature; }))
                co.features[name] = on;
        }
        for (const auto& line : explainSceneFeatures(*scene)) spdlog::info("scene: {}", line);
    }
    for (const auto& [name, on] : options.features) {
        // Said beside the scene's lines above, which the command line overrules.
        if (const auto set = co.features.find(name); set != co.features.end() && set->second != on)
            spdlog::info("feature {} = {}: --feature overrules the scene's {}", name, on ? "on" : "off",
                         set->second ? "on" : "off");
        co.features[name] = on;
    }
    co.outputWidth = options.width;
    co.outputHeight = options.height;
    co.aliasing = options.aliasing;
    co.shareTransientsAcrossFrames = options.shareHeapsAcrossFrames;
    co.clobberTransients = options.clobberTransients;
    return in;
}

FrameEnvironment bakeFrameEnvironment(Device& device, const Plan& plan, const FrameInputs& inputs,
                                      const RenderOptions& options, std::shared_ptr<ShaderCompiler> shaders) {
    // The environment pipeline runs once, now (the environment does not change during a
    // run), and builds only the products this plan samples; its renderer keeps them alive.
    FrameEnvironment env;
    if (!inputs.environment) return env;
    const std::optional<GraphDesc> envGraph = loadEnvironmentGraph(options, inputs.registry);
    env.products = environmentProducts(plan, inputs.graph, envGraph ? &*envGraph : nullptr);
    if (env.products.empty()) return env;
    env.graph = *envGraph;
    if (inputs.environmentSizes)
        resizeEnvironmentGraph(*env.graph,
                               sizesForEnvironmentGraph(*inputs.environmentSizes, inputs.graph, *env.graph));
    try {
        env.renderer =
            bakeForFrame(device, *env.graph, *inputs.environment, env.products, inputs.passes, std::move(shaders));
    } catch (const DeviceCapacityError& e) {
        // The equirect is as large as the scene's file. A cube sized for the view is the least
        // of what the file's width holds, what the view resolves and what the frame graph
        // declares; any other resource is as the environment graph declares it.
        const SceneEnvironment* sky = environmentFile(inputs);
        const bool sizedForView =
            inputs.environmentSizes && (e.resource() == kEnvironment || e.resource() == kPrefiltered);
        if (sky && (e.resource() == kEquirect || (sizedForView && inputs.environmentSizes->boundBySource)))
            throwAtEnvironmentFile(inputs, *sky, e, " to bake");
        if (sizedForView) throwAtDeclaration(inputs.graph, e, nullptr);
        if (e.resource().empty())  // the bake's resources together: named by its graph
            throwInGraph(*env.graph, nullptr, "the environment bake: " + std::string(e.what()));
        throwAtDeclaration(*env.graph, e, nullptr);
    }
    return env;
}

namespace {

/// `attach()`, which gives the frame graph's resource `name` its image or pixels, with its
/// refusal named at that resource's declaration: the declaration is what disagrees with the
/// environment pipeline's product or the scene's file.
template <class Attach>
void attachAtDeclaration(const FrameInputs& inputs, std::string_view name, Attach&& attach) {
    try {
        attach();
    } catch (const ExecutorError& e) {
        const ResourceDesc* declared = inputs.graph.findResource(name);
        if (!declared) throw;
        throwInGraph(inputs.graph, declared, e.what());
    }
}

}  // namespace

void attachFrameInputs(Renderer& renderer, FrameInputs& inputs, const FrameEnvironment& environment) {
    if (inputs.scene) renderer.frameData().set(*inputs.scene);
    for (const auto& name : environment.products)
        attachAtDeclaration(inputs, name, [&] { renderer.importImage(name, environment.renderer->shareImage(name)); });
    // A sequence's sky fades from the previous frame's cube: until there is one, the first.
    if (environment.products.contains(kEnvironment) && renderer.plan().resourceIndex(kEnvironmentPrevious) >= 0)
        attachAtDeclaration(inputs, kEnvironmentPrevious, [&] {
            renderer.importImage(std::string(kEnvironmentPrevious),
                                 environment.renderer->shareImage(std::string(kEnvironment)));
        });
    if (inputs.environment && renderer.plan().resourceIndex(kEquirect) >= 0)
        attachAtDeclaration(inputs, kEquirect, [&] {
            renderer.setExternalImage(std::string(kEquirect), toImageData(std::move(*inputs.environment)));
        });
}

UploadPassPixels::UploadPassPixels(Device& device, const Renderer& renderer, const std::optional<HdrImage>& environment) {
    const Plan& plan = renderer.plan();
    for (const PlannedPass& pass : plan.passes()) {
        if (pass.type != kUploadPass || pass.usages.empty()) continue;
        const std::string target(plan.resources()[pass.usages[0].resource].name);
        const VkDeviceSize bytes = renderer.stagingBytes(target);
        auto buffer = StagingBuffer::create(device, bytes);
        const bool fromEnvironment =
            target == kEquirect && environment && environment->rgba.size() * sizeof(float) == bytes;
        if (fromEnvironment) std::memcpy(buffer->bytes().data(), environment->rgba.data(), bytes);
        else std::memset(buffer->bytes().data(), 0, bytes);
        staged_.emplace_back(target, std::move(buffer));
    }
}

void UploadPassPixels::stageFor(Renderer& renderer) const {
    for (const auto& [resource, buffer] : staged_) renderer.stageUpload(resource, buffer);
}

void throwAtDeclaration(const GraphDesc& graph, const DeviceCapacityError& e, const CompileOptions* compiled) {
    const ResourceDesc* declared = e.resource().empty() ? nullptr : graph.findResource(e.resource());
    std::string message = e.what();  // it names the resource, if one, or says the output size
    if (compiled && declared && declared->extent.relativeToOutput)
        message += " (its extent follows the output, " + std::to_string(compiled->outputWidth) + "x" +
                   std::to_string(compiled->outputHeight) + ")";
    throwInGraph(graph, declared, std::move(message));
}

void throwAtDeclaration(const GraphDesc& graph, const UnsupportedResourceError& e) {
    const ResourceDesc* declared = graph.findResource(e.resource());
    if (!declared) throw e;
    throwInGraph(graph, declared, e.what());
}

void throwCapacityError(const FrameInputs& inputs, const CompileOptions& compiled, const DeviceCapacityError& e) {
    if (e.resource() == kEquirect)
        if (const SceneEnvironment* sky = environmentFile(inputs)) throwAtEnvironmentFile(inputs, *sky, e, "");
    throwAtDeclaration(inputs.graph, e, &compiled);
}

RenderedFrames renderFrames(Device& device, CompiledGraph compiled, FrameInputs& inputs, const RenderOptions& options) {
    RenderedFrames out;
    out.environment = bakeFrameEnvironment(device, compiled.plan(), inputs, options);
    RendererOptions ropts;
    ropts.framesInFlight = options.framesInFlight;
    ropts.passes = inputs.passes;
    const CompileOptions compiledWith = compiled.options();  // `compiled` moves into the renderer
    try {
        out.renderer = std::make_unique<Renderer>(device, std::move(compiled), ropts);
    } catch (const DeviceCapacityError& e) {
        throwCapacityError(inputs, compiledWith, e);
    } catch (const UnsupportedResourceError& e) {
        throwAtDeclaration(inputs.graph, e);
    }
    const UploadPassPixels uploads(device, *out.renderer, inputs.environment);
    attachFrameInputs(*out.renderer, inputs, out.environment);
    for (uint32_t i = 0; i < options.frames; ++i) {
        uploads.stageFor(*out.renderer);
        out.renderer->renderFrame();
        if (options.onFrameSubmitted) options.onFrameSubmitted(i + 1, options.frames);
    }
    out.renderer->waitIdle();
    return out;
}

namespace {

/// The file among those a render reads (the graph, the scene, the environment file or a
/// sequence's frames, the glTF models and what they read) that `output` names, if any:
/// writing it would destroy an input. Gathered only when `output` exists.
std::optional<std::filesystem::path> inputAt(const std::filesystem::path& output, const RenderOptions& options,
                                             const FrameInputs& inputs) {
    std::error_code ec;
    if (output.empty() || !std::filesystem::exists(output, ec)) return std::nullopt;
    std::vector<std::filesystem::path> inputFiles{options.graph, options.scene};
    if (inputs.scene && inputs.scene->environment && !inputs.scene->environment->procedural) {
        const SceneEnvironment& environment = *inputs.scene->environment;
        inputFiles.push_back(environment.file);
        if (environment.sequence)
            for (uint32_t i = 0; i < environment.sequence->count; ++i)
                inputFiles.push_back(environment.sequence->frame(i));
    }
    if (inputs.scene)
        for (const SceneObject& object : inputs.scene->objects)
            if (const auto* model = std::get_if<GltfModel>(&object.shape)) {
                inputFiles.push_back(model->mesh->file);
                inputFiles.insert(inputFiles.end(), model->mesh->referencedFiles.begin(),
                                  model->mesh->referencedFiles.end());
            }
    return files::sameFileAmong(output, inputFiles);
}

/// The file format of the image render writes ("png", "hdr" or "exr"): RenderOptions::
/// outputFormat, else the extension of -o. Null after reporting a name that says neither, or
/// one that contradicts the format given.
std::optional<std::string> outputFormat(const RenderOptions& options) {
    constexpr std::array<std::string_view, 3> kFormats{"png", "hdr", "exr"};
    const auto known = [&](std::string_view f) { return std::find(kFormats.begin(), kFormats.end(), f) != kFormats.end(); };
    for (const std::string_view format : kFormats)
        if (fileNameIsOnlyExtension(options.output, "." + std::string(format))) {
            std::cerr << "skygraph render: " << noStemMessage("-o", options.output, "frame") << "\n";
            return std::nullopt;
        }
    std::string fromName = lowercaseExtension(options.output);
    if (!fromName.empty()) fromName.erase(0, 1);  // the dot
    if (!options.outputFormat.empty()) {
        if (!known(options.outputFormat)) {
            std::cerr << "skygraph render: --format must be png, hdr or exr, got '" << options.outputFormat << "'\n";
            return std::nullopt;
        }
        if (!fromName.empty() && fromName != options.outputFormat) {
            std::cerr << "skygraph render: -o '" << printableName(options.output.string()) << "' names a ." << fromName
                      << " file but --format is " << options.outputFormat << "\n";
            return std::nullopt;
        }
        return options.outputFormat;
    }
    if (options.output.empty()) return "png";
    if (std::error_code ec; std::filesystem::is_directory(options.output, ec)) {
        std::cerr << "skygraph render: cannot write '" << printableName(options.output.string()) << "': it is a folder\n";
        return std::nullopt;
    }
    if (!known(fromName)) {
        std::cerr << "skygraph render: cannot write '" << printableName(options.output.string())
                  << "': its extension must be .png, .hdr or .exr, or --format must say which (e.g. -o /dev/stdout "
                     "--format exr)\n";
        return std::nullopt;
    }
    return fromName;
}

/// Writes `image` as `format`. A PNG holds sRGB-encoded bytes, as a presented image or an
/// *_SRGB one does; .hdr and .exr hold linear values, so those two are decoded for them (the
/// presented image is encoded in either format: by the hardware for *_SRGB, by the tone
/// mapper otherwise, as the sRGB-nonlinear swapchain expects). Any other image is written as
/// stored.
void writeImage(const std::filesystem::path& output, ImageData image, std::string_view format, bool presented) {
    if (format == "png") return writePng(output, image);
    const std::optional<FormatInfo> info = findFormat(image.format);
    if (presented || (info && info->srgb))
        for (size_t i = 0; i < image.rgba.size(); ++i)
            if (i % 4 != 3) image.rgba[i] = math::srgbDecode(image.rgba[i]);
    if (format == "hdr") return saveRadianceHdr(output, toHdrImage(image));
    saveExr(output, toHdrImage(image));
}

}  // namespace

int renderCommand(const RenderOptions& options) {
    try {
        if (options.graph.empty() && options.graphText.empty()) {
            std::cerr << "skygraph render: no graph file given\n";
            return 1;
        }
        if (options.width == 0 || options.height == 0 || options.frames == 0) {
            std::cerr << "skygraph render: --width, --height and --frames must be at least 1\n";
            return 1;
        }
        const std::optional<std::string> chosenFormat = outputFormat(options);
        if (!chosenFormat) return 1;
        const std::string& format = *chosenFormat;
        FrameInputs inputs = loadFrameInputs(options);
        const GraphDesc& graph = inputs.graph;
        CompileOptions co = inputs.compile;
        // Headless: the swapchain target is an image of our own, read back instead of presented.
        co.presentReplacement = ExternalState::TransferSrc;
        std::filesystem::path output = options.output;
        const Plan unread = compile(graph, co);
        const std::string target = outputTarget(graph, unread, options.readback);
        const std::set<std::string, std::less<>> written = writtenByPasses(unread);
        // Said here, not by compile(): it would report the name at the file's `resources`, and the
        // name came from the command line.
        if (!options.readback.empty() && !graph.findResource(options.readback)) {
            const std::string images = writtenImageNames(graph, written);
            std::cerr << "skygraph render: " << printableName(graph.file) << ": cannot read back '"
                      << printableName(options.readback) << "' (--readback): the graph has no resource of that name"
                      << (images.empty() ? std::string() : "; the images its passes write: " + images) << "\n";
            return 1;
        }
        if (target.empty()) {
            if (!output.empty()) {
                const std::string images = writtenImageNames(graph, written);
                std::cerr << "skygraph render: " << printableName(graph.file) << ": nothing to write to -o '"
                          << printableName(output.string()) << "': the graph has no Present image that a pass uses; "
                          << (images.empty() ? std::string("nor any image that a pass writes, to read back")
                                             : "add --readback NAME with one of the images its passes write: " + images)
                          << "\n";
                return 1;
            }
            spdlog::info("graph '{}' has no Present image that a pass uses: no file is written (-o FILE --readback NAME "
                         "writes one)",
                         graph.name);
        } else {
            // An output of the graph (exported) that no pass of these features writes would be
            // read back as the placeholder it arrives with.
            const ResourceDesc* declared = graph.findResource(target);
            if (declared && declared->external && declared->isExported() && !written.contains(target)) {
                const std::string images = writtenImageNames(graph, written);
                std::cerr << "skygraph render: " << printableName(graph.file) << ": cannot read back '" << target
                          << "': it is an output of the graph, and no pass that runs with these features writes it"
                          << (images.empty() ? std::string() : "; the images its passes write: " + images) << "\n";
                return 1;
            }
            // Before a device is made: the file's declaration is what to change.
            if (declared && declared->isImage())
                if (std::string problem = readbackProblem(target, declared->format.format); !problem.empty()) {
                    Diagnostics d;
                    d.add({graph.file, declared->jsonPath(), "", target, std::move(problem)});
                    throw GraphError(std::move(d));
                }
            if (output.empty()) output = "skygraph." + format;
            co.readbacks = {target};
        }
        if (const auto input = inputAt(output, options, inputs)) {
            std::cerr << "skygraph render: " << (options.output.empty() ? "the default output '" : "-o '")
                      << printableName(output.string()) << "' is the input '" << printableName(input->string())
                      << "': it would be overwritten\n";
            return 1;
        }
        if (!output.empty()) {  // before the render: a mistyped folder costs no work
            try {
                (void)files::writableOutputTarget(output);
            } catch (const std::filesystem::filesystem_error& e) {
                std::cerr << "skygraph render: cannot write '" << printableName(output.string()) << "': " << files::whyNotWritten(e)
                          << "\n";
                return 1;
            }
        }
        CompiledGraph compiled(graph, co);
        for (const auto& c : compiled.plan().culled()) spdlog::info("culled {}: {}", c.name, c.reason);

        DeviceOptions dopts;
        dopts.device = options.device;
        dopts.validation = options.validate;
        auto device = Device::create(dopts);
        const RenderedFrames frames = renderFrames(*device, std::move(compiled), inputs, options);
        Renderer& renderer = *frames.renderer;
        for (const auto& t : renderer.lastTimings()) {
            spdlog::info("pass {:<24} {:8.3f} ms (GPU)", t.pass, t.milliseconds);
        }
        std::optional<ImageData> image;
        if (!target.empty()) image = renderer.readback(target);
        // A frame validation complained about is no result: exit 1 writes nothing.
        if (const int status = validationExit(*device, "skygraph render"); status != 0) {
            if (image) std::cerr << "skygraph render: '" << printableName(output.string()) << "' not written\n";
            return status;
        }
        if (image) {
            writeImage(output, std::move(*image), format, options.readback.empty());
            spdlog::info("wrote {}", printableName(output.string()));
        }
        return 0;
    } catch (...) {
        return exitForCurrentException("skygraph render");
    }
}

}  // namespace skygraph::app
