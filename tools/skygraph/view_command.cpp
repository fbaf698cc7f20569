#include "view_command.hpp"

#include "builtin_defaults.hpp"
#include "builtin_ibl_graph.hpp"

#include "app/view.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/shader_compiler.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <map>
#include <memory>

namespace skygraph::cli {
namespace {

struct ViewArgs {
    app::ViewOptions options;
    std::string graph, scene, presentMode = "fifo";
    std::vector<std::string> features;
};

int run(ViewArgs& args) {
    static const PassLibrary library = PassLibrary::withBuiltins();
    app::ViewOptions options = args.options;
    app::RenderOptions& frame = options.frame;
    frame.passes = &library;
    if (args.graph.empty()) {  // the defaults of `render`
        frame.graphText = kDefaultGraph;
        if (args.scene.empty()) frame.sceneText = kDefaultScene;
        frame.environmentGraphText = kIblGraph;
    }
    frame.graph = args.graph;
    frame.scene = args.scene;
    frame.features = parseFeatureFlags(args.features);
    options.presentMode = args.presentMode == "mailbox"     ? PresentMode::Mailbox
                          : args.presentMode == "immediate" ? PresentMode::Immediate
                                                            : PresentMode::Fifo;
    spdlog::debug("shaders from {}", ShaderCompiler::defaultIncludeDir().string());
    return app::viewCommand(options);
}

}  // namespace

Command addViewCommand(CLI::App& parent) {
    auto args = std::make_shared<ViewArgs>();
    app::ViewOptions& o = args->options;
    CLI::App* cmd = parent.add_subcommand(
        "view", "Present a graph in a window (GLFW) until it is closed. With no graph and no scene: the built-in "
                "raster graph and default scene. Left-drag orbits the camera, the wheel zooms, Escape closes. A saved "
                "graph, scene or shader file reloads; a broken one shows its error and keeps the last good frame");
    cmd->add_option("graph", args->graph, "Graph file (default: the built-in graphs/raster.json)")->check(kNotEmpty);
    cmd->add_option("--scene", args->scene, "Scene file (scenes/*.json); default with the built-in graph: "
                                            "the built-in scenes/default.json")
        ->check(kNotEmpty);
    cmd->add_option("--feature", args->features, "Override a feature: NAME=on|off (repeatable)");
    cmd->add_option("--width", o.frame.width, "Window width")->check(CLI::Range(1u, 16384u))->capture_default_str();
    cmd->add_option("--height", o.frame.height, "Window height")->check(CLI::Range(1u, 16384u))->capture_default_str();
    cmd->add_option("--frames", o.frames, "Quit after presenting this many frames (default: when the window closes)")
        ->check(CLI::Range(1u, 100000000u));
    cmd->add_option("--frames-in-flight", o.frame.framesInFlight, "Frames in flight")
        ->check(CLI::Range(1u, 8u))->capture_default_str();
    cmd->add_option("--present-mode", args->presentMode, "fifo (default), mailbox or immediate; fifo when the "
                                                         "surface lacks it")
        ->check(CLI::IsMember({"fifo", "mailbox", "immediate"}));
    addFlagSettingFalse(*cmd, "--no-fit-environment", o.frame.fitEnvironmentToView,
                        "Build the environment cube and the prefiltered cube at the graph's declared sizes");
    addFlagSettingFalse(*cmd, "--no-alias", o.frame.aliasing,
                        "Give every transient resource of the frame memory of its own (no aliasing barriers)");
    addFlagSettingFalse(*cmd, "--heaps-per-frame", o.frame.shareHeapsAcrossFrames,
                        "A copy of the transients' heaps per frame in flight, instead of one the frames share");
    cmd->add_flag("--clobber-transients", o.frame.clobberTransients,
                  "Fill each transient resource that is not cleared with poison (NaN where the format holds it) "
                  "before its first use");
    addFlagSettingFalse(*cmd, "--no-ui", o.overlay, "Hide the debug overlay (the graph's feature ui off)");
    cmd->add_flag("--validate", o.frame.validate,
                  "Khronos validation with synchronization validation; any warning or error fails (performance "
                  "advice is logged)");
    cmd->add_option("--device", o.frame.device, "Device by index or name")->check(kNotEmpty);
    return {cmd, [args] { return run(*args); }};
}

}  // namespace skygraph::cli
