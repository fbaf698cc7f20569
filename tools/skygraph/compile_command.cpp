#include "compile_command.hpp"

#include "file_watcher.hpp"
#include "text_diff.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/plan_format.hpp>
#include <skygraph/transfer_plans.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

namespace skygraph::cli {
namespace {

struct CompileArgs {
    std::string graph;
    std::vector<std::string> features;
    std::string format = "text";
    std::string output;
    bool noCull = false;
    bool watch = false;
    uint32_t watchIntervalMs = 250;
    uint32_t watchIterations = 0;  // 0: until interrupted
};

/// One successful compilation: the text listing (what --watch diffs) and the requested format.
struct CompiledPlan {
    std::string text;
    std::string formatted;
};

CompiledPlan compileOnce(const CompileArgs& args, const FeatureValues& features) {
    const auto start = std::chrono::steady_clock::now();
    const PassRegistry registry = PassRegistry::withBuiltins();
    const GraphDesc graph = loadGraphFile(args.graph, registry);
    CompileOptions options;
    options.features = features;
    options.cull = !args.noCull;
    const Plan plan = compile(graph, options);
    spdlog::debug("{}: {} passes and {} resources -> {} passes run, {} culled, in {:.2f} ms", args.graph,
                  graph.passes.size(), graph.resources.size(), plan.passes().size(), plan.culled().size(),
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    // What runs once before the first frame belongs to the plan as much as the frame does.
    const Plan setup = planSetup(graph, plan);
    CompiledPlan out;
    out.text = planToText(plan);
    if (!setup.passes().empty()) out.text += "\nsetup, once before the first frame:\n" + planToText(setup);
    if (args.format == "json") {
        auto j = planToJson(plan);
        if (!setup.passes().empty()) j["setup"] = planToJson(setup);
        out.formatted = j.dump(2) + "\n";
    }
    else if (args.format == "dot") out.formatted = planToDot(plan, graph, &setup);
    else out.formatted = out.text;
    return out;
}

std::atomic<bool> gStopWatching{false};
void stopWatching(int) { gStopWatching = true; }

/// --watch: the first plan in full, then on each save the diff of the text plan. A graph that
/// stops compiling prints its errors and the last good plan stays (the -o file too).
int watch(const CompileArgs& args, const FeatureValues& features) {
    std::signal(SIGINT, stopWatching);
    std::signal(SIGTERM, stopWatching);
    app::FileWatcher watcher(args.graph);
    std::optional<CompiledPlan> last;
    auto rebuild = [&] {
        try {
            CompiledPlan now = compileOnce(args, features);
            if (!args.output.empty()) writeOutput(args.output, now.formatted);
            if (!last) {
                if (args.output.empty()) writeOutput({}, now.formatted);
            } else if (const std::string diff = unifiedDiff(last->text, now.text, "plan (before)", "plan (now)");
                       diff.empty()) {
                std::cout << "plan unchanged\n" << std::flush;
            } else {
                std::cout << diff << std::flush;
            }
            last = std::move(now);
        } catch (...) {
            (void)reportCurrentException();
            if (last) spdlog::warn("keeping the last plan that compiled");
        }
    };
    rebuild();
    spdlog::info("watching {} for changes (Ctrl-C stops)", args.graph);
    for (uint32_t rebuilds = 0; !gStopWatching;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(args.watchIntervalMs));
        if (!watcher.changed()) continue;
        spdlog::info("{} changed: recompiling", args.graph);
        rebuild();
        if (args.watchIterations != 0 && ++rebuilds >= args.watchIterations) break;
    }
    return last ? kExitOk : kExitUserError;
}

int run(const CompileArgs& args) {
    const FeatureValues features = parseFeatureFlags(args.features);
    if (args.watch) return watch(args, features);
    writeOutput(args.output, compileOnce(args, features).formatted);
    return kExitOk;
}

}  // namespace

Command addCompileCommand(CLI::App& parent) {
    auto args = std::make_shared<CompileArgs>();
    CLI::App* cmd = parent.add_subcommand("compile", "Compile a graph file into a plan of passes and barriers");
    cmd->add_option("graph", args->graph, "Graph file (graphs/*.json)")->required();
    cmd->add_option("--feature", args->features, "Override a feature: NAME=on|off (repeatable)");
    cmd->add_option("--format", args->format, "Output format: text, json (schemas/plan.schema.json) or dot (graphviz)")
        ->check(CLI::IsMember({"text", "json", "dot"}));
    cmd->add_option("-o,--output", args->output, "Write to FILE instead of stdout (never half-written)");
    cmd->add_flag("--no-cull", args->noCull, "Keep passes whose output nobody reads");
    cmd->add_flag("--watch", args->watch,
                  "Recompile whenever GRAPH is saved and print the text plan's diff (until Ctrl-C)");
    cmd->add_option("--watch-interval-ms", args->watchIntervalMs, "How often --watch looks at GRAPH")
        ->check(CLI::Range(10u, 60000u));
    cmd->add_option("--watch-iterations", args->watchIterations,
                    "Stop --watch after this many recompilations (0: never; for scripts and tests)");
    return {cmd, [args] { return run(*args); }};
}

}  // namespace skygraph::cli
