// The skygraph command line (contract §3). Exit status: 0 success, 1 user error (message on
// stderr, nothing half-written), 2 misuse of the command line.
#include "cli_common.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>
#if SKYGRAPH_HAS_EXECUTOR
#include "builtin_defaults.hpp"

#include <skygraph/executor.hpp>
#include <skygraph/pass.hpp>
#endif

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <iostream>

namespace {

using namespace skygraph;
using namespace skygraph::cli;

struct CompileArgs {
    std::string graph;
    std::vector<std::string> features;
    std::string format = "text";
    std::string output;
    bool noCull = false;
};

int runCompile(const CompileArgs& args) {
    const PassRegistry registry = PassRegistry::withBuiltins();
    const GraphDesc graph = loadGraphFile(args.graph, registry);
    CompileOptions options;
    options.features = parseFeatureFlags(args.features);
    options.cull = !args.noCull;
    const Plan plan = compile(graph, options);
    std::string text;
    if (args.format == "json") text = planToJson(plan).dump(2) + "\n";
    else if (args.format == "dot") text = planToDot(plan, graph);
    else text = planToText(plan);
    writeOutput(args.output, text);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"skygraph: a data-driven Vulkan render graph"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "skygraph 0.1.0");
    bool verbose = false, quiet = false;
    app.add_flag("-v,--verbose", verbose, "Log debug messages");
    app.add_flag("-q,--quiet", quiet, "Log errors only");

    CompileArgs compileArgs;
    auto* compileCmd = app.add_subcommand("compile", "Compile a graph file into a plan of passes and barriers");
    compileCmd->add_option("graph", compileArgs.graph, "Graph file (graphs/*.json)")->required();
    compileCmd->add_option("--feature", compileArgs.features, "Override a feature: NAME=on|off (repeatable)");
    compileCmd->add_option("--format", compileArgs.format, "Output format")
        ->check(CLI::IsMember({"text", "json", "dot"}));
    compileCmd->add_option("-o,--output", compileArgs.output, "Write to FILE instead of stdout");
    compileCmd->add_flag("--no-cull", compileArgs.noCull, "Keep passes whose output nobody reads");

#if SKYGRAPH_HAS_EXECUTOR
    RenderOptions renderArgs;
    std::string renderGraph, renderScene, renderOutput = "skygraph.png";
    std::vector<std::string> renderFeatures;
    auto* renderCmd = app.add_subcommand(
        "render", "Render a graph headless and write the swapchain target. With no graph and no scene: "
                  "the built-in raster graph and default scene");
    renderCmd->add_option("graph", renderGraph, "Graph file (default: the built-in graphs/raster.json)");
    renderCmd->add_option("--scene", renderScene, "Scene file (scenes/*.json); default with the built-in graph: "
                                                  "the built-in scenes/default.json");
    renderCmd->add_option("--feature", renderFeatures, "Override a feature: NAME=on|off (repeatable)");
    renderCmd->add_option("--width", renderArgs.width, "Output width")->check(CLI::Range(1u, 16384u));
    renderCmd->add_option("--height", renderArgs.height, "Output height")->check(CLI::Range(1u, 16384u));
    renderCmd->add_option("--frames", renderArgs.frames, "Frames to render")->check(CLI::Range(1u, 100000u));
    renderCmd->add_option("--frames-in-flight", renderArgs.framesInFlight, "Frames in flight")
        ->check(CLI::Range(1u, 8u));
    renderCmd->add_option("-o,--output", renderOutput, "Write the result: .png, .hdr or .exr (default skygraph.png)");
    renderCmd->add_option("--readback", renderArgs.readback,
                          "Write this resource instead of the swapchain target (e.g. hdr_color to .exr)");
    renderCmd->add_flag("--validate", renderArgs.validate,
                        "Khronos validation with synchronization validation; any message fails");
    renderCmd->add_option("--device", renderArgs.device, "Device by index or name");
#endif

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);  // prints help or the parse error
        return code == 0 ? 0 : 2;
    }
    spdlog::set_level(quiet ? spdlog::level::err : verbose ? spdlog::level::debug : spdlog::level::info);

    return runGuarded([&] {
        if (compileCmd->parsed()) return runCompile(compileArgs);
#if SKYGRAPH_HAS_EXECUTOR
        if (renderCmd->parsed()) {
            static const PassLibrary library = PassLibrary::withBuiltins();
            renderArgs.passes = &library;
            if (renderGraph.empty()) {
                renderArgs.graphText = kDefaultGraph;
                if (renderScene.empty()) renderArgs.sceneText = kDefaultScene;
            }
            renderArgs.graph = renderGraph;
            renderArgs.scene = renderScene;
            renderArgs.output = renderOutput;
            renderArgs.features = parseFeatureFlags(renderFeatures);
            return renderCommand(renderArgs);
        }
#endif
        return 2;
    });
}
