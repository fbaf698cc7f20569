#include "render_command.hpp"

#include "builtin_defaults.hpp"
#include "builtin_ibl_graph.hpp"
#include "progress_bar.hpp"

#include "app/render.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/shader_compiler.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <memory>
#include <optional>

namespace skygraph::cli {
namespace {

struct RenderArgs {
    app::RenderOptions options;
    std::string graph, scene, output;
    std::vector<std::string> features;
};

int run(RenderArgs& args) {
    static const PassLibrary library = PassLibrary::withBuiltins();
    app::RenderOptions options = args.options;
    options.passes = &library;
    if (args.graph.empty()) {
        options.graphText = kDefaultGraph;
        if (args.scene.empty()) options.sceneText = kDefaultScene;
        options.environmentGraphText = kIblGraph;  // a scene with a file environment needs it
    }
    options.graph = args.graph;
    options.scene = args.scene;
    options.output = args.output;
    options.features = parseFeatureFlags(args.features);
    spdlog::debug("shaders from {}", ShaderCompiler::defaultIncludeDir().string());
    std::optional<ProgressBar> bar;
    options.onFrameSubmitted = [&](uint32_t submitted, uint32_t total) {
        if (!bar) bar.emplace("render", total, "frames");
        bar->advance(submitted - bar->done());
        if (submitted == total) bar->finish();  // before the timings and "wrote" lines
    };
    return app::renderCommand(options);
}

}  // namespace

Command addRenderCommand(CLI::App& parent) {
    auto args = std::make_shared<RenderArgs>();
    app::RenderOptions& o = args->options;
    CLI::App* cmd = parent.add_subcommand(
        "render", "Render a graph headless and write the swapchain target. With no graph and no scene: "
                  "the built-in raster graph and default scene");
    cmd->add_option("graph", args->graph, "Graph file (default: the built-in graphs/raster.json)")->check(kNotEmpty);
    cmd->add_option("--scene", args->scene, "Scene file (scenes/*.json); default with the built-in graph: "
                                            "the built-in scenes/default.json")
        ->check(kNotEmpty);
    cmd->add_option("--feature", args->features, "Override a feature: NAME=on|off (repeatable)");
    cmd->add_option("--width", o.width, "Output width")->check(CLI::Range(1u, 16384u))->capture_default_str();
    cmd->add_option("--height", o.height, "Output height")->check(CLI::Range(1u, 16384u))->capture_default_str();
    cmd->add_option("--frames", o.frames, "Frames to render")->check(CLI::Range(1u, 100000u))->capture_default_str();
    cmd->add_option("--frames-in-flight", o.framesInFlight, "Frames in flight")
        ->check(CLI::Range(1u, 8u))->capture_default_str();
    cmd->add_option("-o,--output", args->output,
                    "Write the result: .png, .hdr or .exr (default skygraph.png or skygraph.FORMAT, when the graph has a Present image "
                    "or --readback names one)")
        ->check(kNotEmpty);
    cmd->add_option("--format", o.outputFormat,
                    "The image's format: png, hdr or exr (default: by the extension of -o), for a name "
                    "without an extension such as /dev/stdout")
        ->check(CLI::IsMember({"png", "hdr", "exr"}));
    cmd->add_option("--readback", o.readback,
                    "Write this resource instead of the swapchain target (e.g. hdr_color to .exr)")
        ->check(kNotEmpty);
    addFlagSettingFalse(*cmd, "--no-fit-environment", o.fitEnvironmentToView,
                        "Build the environment cube and the prefiltered cube at the graph's declared sizes, not at "
                        "the sizes the view can show (output height, field of view, equirect width)");
    addFlagSettingFalse(*cmd, "--no-alias", o.aliasing,
                        "Give every transient resource of the frame memory of its own (no aliasing barriers)");
    addFlagSettingFalse(*cmd, "--heaps-per-frame", o.shareHeapsAcrossFrames,
                        "A copy of the transients' heaps per frame in flight, instead of one the frames share");
    cmd->add_flag("--clobber-transients", o.clobberTransients,
                  "Fill each transient resource that is not cleared with poison (NaN where the format holds it) "
                  "before its first use: a frame that then renders differently reads what it did not write");
    cmd->add_flag("--validate", o.validate,
                  "Khronos validation with synchronization validation; any warning or error fails (performance "
                  "advice is logged)");
    cmd->add_option("--device", o.device, "Device by index or name")->check(kNotEmpty);
    return {cmd, [args] { return run(*args); }};
}

}  // namespace skygraph::cli
