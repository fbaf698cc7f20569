// `skygraph render`: compile a graph file and render it headless.
#include <skygraph/compiler.hpp>
#include <skygraph/hdr_image.hpp>
#include <skygraph/executor.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>

#include <spdlog/spdlog.h>

#include <cstdio>
#include <optional>
#include <iostream>

namespace skygraph {
namespace {

/// The graph resource that a loaded environment file becomes (graphs/raster.json, ibl.json).
constexpr std::string_view kEnvironmentResource = "env_equirect";

bool setEnvironmentExtent(GraphDesc& graph, const HdrImage& image) {
    for (ResourceDesc& r : graph.resources) {
        if (r.name != kEnvironmentResource) continue;
        r.extent = Extent{false, 1, image.width, image.height};
        return true;
    }
    return false;
}

ImageData toImageData(HdrImage&& image) {
    ImageData d;
    d.width = image.width;
    d.height = image.height;
    d.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    d.rgba = std::move(image.rgba);
    return d;
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
        const PassRegistry builtins = options.passes ? PassRegistry{} : PassRegistry::withBuiltins();
        const PassRegistry& registry = options.passes ? options.passes->registry() : builtins;
        GraphDesc graph = options.graphText.empty()
                                    ? loadGraphFile(options.graph, registry)
                                    : parseGraph(options.graphText, "<built-in raster.json>", registry);
        std::optional<Scene> scene;
        if (!options.sceneText.empty())
            scene = parseScene(options.sceneText, "<built-in default scene>", std::filesystem::current_path());
        else if (!options.scene.empty())
            scene = loadSceneFile(options.scene);
        // A file environment is loaded before compiling: its size is the extent of the graph's
        // `env_equirect` (data-driven, so the plan's subresources match the image).
        std::optional<HdrImage> environment;
        if (scene && scene->environment && !scene->environment->procedural) {
            environment = loadHdrImage(scene->environment->file);
            spdlog::info("environment: {} ({}x{})", scene->environment->file.string(), environment->width,
                         environment->height);
            if (!setEnvironmentExtent(graph, *environment))
                spdlog::warn("graph '{}' has no resource 'env_equirect': the environment file is not used",
                             graph.name);
        }
        CompileOptions co;
        if (scene) {
            co.features = sceneFeatures(*scene);
            for (const auto& line : explainSceneFeatures(*scene)) spdlog::info("scene: {}", line);
        }
        for (const auto& [name, on] : options.features) co.features[name] = on;
        co.presentReplacement = ExternalState::TransferSrc;
        if (!options.readback.empty()) co.exports[options.readback] = ExternalState::TransferSrc;
        co.outputWidth = options.width;
        co.outputHeight = options.height;
        Plan plan = compile(graph, co);
        for (const auto& c : plan.culled) spdlog::info("culled {}: {}", c.name, c.reason);

        DeviceOptions dopts;
        dopts.device = options.device;
        dopts.validation = options.validate;
        auto device = Device::create(dopts);
        RendererOptions ropts;
        ropts.width = options.width;
        ropts.height = options.height;
        ropts.framesInFlight = options.framesInFlight;
        ropts.passes = options.passes;
        ropts.readback = options.readback;
        Renderer renderer(*device, graph, std::move(plan), ropts);
        if (scene) renderer.frameData().set(*scene);
        if (environment && renderer.plan().resourceIndex(kEnvironmentResource) >= 0)
            renderer.setExternalImage(std::string(kEnvironmentResource), toImageData(std::move(*environment)));
        for (uint32_t i = 0; i < options.frames; ++i) {
            renderer.renderFrame();
            if (options.onFrameSubmitted) options.onFrameSubmitted(i + 1, options.frames);
        }
        renderer.waitIdle();
        for (const auto& t : renderer.lastTimings()) {
            spdlog::info("pass {:<24} {:8.3f} ms (GPU)", t.pass, t.milliseconds);
        }
        if (!options.output.empty()) {
            const ImageData image = renderer.readback();
            const auto ext = options.output.extension().string();
            if (ext == ".hdr" || ext == ".exr") {
                writeHdr(options.output, image);
            } else {
                writePng(options.output, image);
            }
            spdlog::info("wrote {}", options.output.string());
        }
        if (device->validationEnabled() && device->messageCount() > 0) {
            std::cerr << "skygraph render: validation reported " << device->messageCount()
                      << " message(s)\n";
            return 1;
        }
        return 0;
    } catch (const GraphError& e) {
        std::cerr << e.diagnostics().format() << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "skygraph render: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace skygraph
