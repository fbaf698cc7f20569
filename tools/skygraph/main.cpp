// The skygraph command line (contract §3). Exit status: 0 success, 1 user error (message on
// stderr, nothing half-written), 2 misuse of the command line.
#include "cli_common.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>

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
    RenderArgs renderArgs;
    auto* renderCmd = addRenderCommand(app, renderArgs);
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
        if (renderCmd->parsed()) return runRender(renderArgs);
#endif
        return 2;
    });
}
