#include "compile_command.hpp"

#include "app/presented_images.hpp"
#include "file_watcher.hpp"
#include "printable_name.hpp"
#include "replace_file.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/golden.hpp>
#include <skygraph/plan_format.hpp>
#include <skygraph/transfer_plans.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
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
    uint32_t width = 1920, height = 1080;  // the output size "output" extents resolve to
    bool noAlias = false;
    bool heapsPerFrame = false;
    std::string placement = "best-fit";
    std::string layouts;  // empty: the graph file's setting
    std::string queueFamilies;
    std::string memorySvg;  // where to draw the memory layout; empty: nowhere
    bool watch = false;
    uint32_t watchIntervalMs = 250;
    uint32_t watchIterations = 0;  // 0: until interrupted
};

/// One successful compilation: the text listing (what --watch diffs), the requested format and,
/// with --memory-svg, the memory layout's picture.
struct CompiledPlan {
    std::string text;
    std::string formatted;
    std::string memorySvg;
};

CompileOptions compileOptions(const CompileArgs& args, const FeatureValues& features) {
    CompileOptions options;
    options.features = features;
    options.cull = !args.noCull;
    options.outputWidth = args.width;
    options.outputHeight = args.height;
    options.aliasing = !args.noAlias;
    options.shareTransientsAcrossFrames = !args.heapsPerFrame;
    options.placement = args.placement == "first-use" ? MemoryStrategy::FirstUseOrder : MemoryStrategy::BestFitBySize;
    options.layouts = parseLayoutsFlag(args.layouts);
    options.queueFamilies = parseQueueFamiliesFlag(args.queueFamilies);
    return options;
}

CompiledPlan compileOnce(const CompileArgs& args, const FeatureValues& features) {
    const auto start = std::chrono::steady_clock::now();
    const PassRegistry registry = PassRegistry::withBuiltins();
    const GraphDesc graph = loadGraphFile(args.graph, registry);
    const Plan plan = compile(graph, compileOptions(args, features));
    // What a pass type refuses of its passes as this plan runs them, a renderer would refuse.
    if (Diagnostics problems = plannedPassProblems(plan, graph, registry); !problems.empty())
        throw GraphError(std::move(problems));
    spdlog::debug("{}: {} passes and {} resources -> {} passes run, {} culled, in {:.2f} ms", args.graph,
                  graph.passes.size(), graph.resources.size(), plan.passes().size(), plan.culled().size(),
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    // Not an error, unlike in `check`: a combination is compiled to be looked at, and this one
    // may be looked at because its frame shows nothing.
    if (const std::string why = app::presentsNothing(plan, graph); !why.empty())
        spdlog::warn("{}: {}", printableName(args.graph), why);
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
    if (!args.memorySvg.empty()) out.memorySvg = planMemoryToSvg(plan);
    return out;
}

/// The picture and the plan file are written all or none (exit 1, nothing written); a plan
/// for standard output follows the picture.
void writeCompiled(const CompileArgs& args, const CompiledPlan& compiled, bool planToStdout) {
    if (!args.memorySvg.empty() && !args.output.empty()) {
        const std::filesystem::path both[] = {args.memorySvg, args.output};
        try {
            files::replaceFilesContents(both, [&](size_t i) { return i == 0 ? compiled.memorySvg : compiled.formatted; });
        } catch (const std::filesystem::filesystem_error& e) {
            throw std::runtime_error("cannot write '" + printableName(e.path1().string()) + "': " + files::whyNotWritten(e));
        }
        return;
    }
    if (!args.memorySvg.empty()) writeOutput(args.memorySvg, compiled.memorySvg);
    if (!args.output.empty()) writeOutput(args.output, compiled.formatted);
    else if (planToStdout) writeOutput({}, compiled.formatted);
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
            writeCompiled(args, now, !last);
            if (last) {
                const std::string diff = unifiedDiff(last->text, now.text, "plan (before)", "plan (now)");
                std::cout << (diff.empty() ? "plan unchanged\n" : diff) << std::flush;
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

/// -o and --memory-svg naming one file: the second write would replace the first.
void refuseOneFileForBothOutputs(const CompileArgs& args) {
    if (args.output.empty() || args.memorySvg.empty()) return;
    const std::filesystem::path outputs[] = {args.output, args.memorySvg};
    if (files::twoNamesOfOneFile(outputs))
        throw std::runtime_error("-o and --memory-svg both name '" + printableName(args.output) +
                                 "': the plan would replace the picture");
}

/// --memory-svg naming standard output while the plan is printed there (no -o): the picture is
/// written first, through a name of the stream, and the plan then at standard output's own
/// offset, over the picture in a file and after it in a pipe; neither is a file anyone can read.
/// The same file rather than the same name: /dev/stdout, /proc/self/fd/1, or the file or
/// file that the shell redirected standard output to, under any of its names. Not a device:
/// a terminal shows the picture and then the plan, and /dev/null takes both.
void refusePictureOnThePlansStandardOutput(const CompileArgs& args) {
    if (!args.output.empty() || args.memorySvg.empty()) return;
    struct stat standardOutput {}, picture {};
    if (::fstat(STDOUT_FILENO, &standardOutput) != 0 || ::stat(args.memorySvg.c_str(), &picture) != 0) return;
    if (S_ISCHR(standardOutput.st_mode)) return;
    if (standardOutput.st_dev == picture.st_dev && standardOutput.st_ino == picture.st_ino)
        throw std::runtime_error("--memory-svg '" + printableName(args.memorySvg) +
                                 "' is standard output, where the plan is printed: the plan would be written over "
                                 "the picture or after it; draw the picture to another file, or write the plan "
                                 "with -o");
}

int run(const CompileArgs& args) {
    refuseToOverwriteInputs("-o", args.output, {args.graph});
    refuseToOverwriteInputs("--memory-svg", args.memorySvg, {args.graph});
    refuseOneFileForBothOutputs(args);
    refusePictureOnThePlansStandardOutput(args);
    const FeatureValues features = parseFeatureFlags(args.features);
    if (args.watch) return watch(args, features);
    writeCompiled(args, compileOnce(args, features), true);
    return kExitOk;
}

}  // namespace

Command addCompileCommand(CLI::App& parent) {
    auto args = std::make_shared<CompileArgs>();
    CLI::App* cmd = parent.add_subcommand("compile", "Compile a graph file into a plan of passes and barriers");
    cmd->add_option("graph", args->graph, "Graph file (graphs/*.json)")->required()->check(kNotEmpty);
    cmd->add_option("--feature", args->features, "Override a feature: NAME=on|off (repeatable)");
    cmd->add_option("--format", args->format, "Output format: text, json (schemas/plan.schema.json) or dot (graphviz)")
        ->check(CLI::IsMember({"text", "json", "dot"}));
    cmd->add_option("-o,--output", args->output, "Write to FILE instead of stdout (never half-written)")->check(kNotEmpty);
    cmd->add_flag("--no-cull", args->noCull, "Keep passes whose output nobody reads");
    cmd->add_option("--width", args->width, "Output width that \"output\" extents resolve to (default 1920)")
        ->check(CLI::Range(1u, 16384u));
    cmd->add_option("--height", args->height, "Output height that \"output\" extents resolve to (default 1080)")
        ->check(CLI::Range(1u, 16384u));
    CLI::Option* noAlias = cmd->add_flag(
        "--no-alias", args->noAlias, "Give every transient resource memory of its own (no aliasing barriers)");
    cmd->add_flag("--heaps-per-frame", args->heapsPerFrame,
                  "A copy of the transients' heaps per frame in flight, instead of one the frames share");
    cmd->add_option("--placement", args->placement,
                    "How transient resources share memory: best-fit (largest first, into the tightest gap; the "
                    "default) or first-use (in order of first use, like a frame-by-frame pool); docs/memory.md")
        ->check(CLI::IsMember({"best-fit", "first-use"}))
        ->excludes(noAlias);
    cmd->add_option("--queue-families", args->queueFamilies,
                    "separate (default): the graphics, compute and transfer queues are of three queue families, "
                    "so exclusive resources change owner between them; one: a device with one queue family "
                    "(lavapipe), where only semaphores order the queues")
        ->check(CLI::IsMember({"separate", "one"}));
    cmd->add_option("--layouts", args->layouts,
                    "How a run of reads of an image is laid out: fewest-barriers (one layout for every reader) or "
                    "optimal (each reader's optimal layout, with transitions between); default: the graph's "
                    "\"layouts\", else fewest-barriers")
        ->check(CLI::IsMember({"fewest-barriers", "optimal"}));
    cmd->add_option("--memory-svg", args->memorySvg,
                    "Also draw the memory layout (passes across, byte offsets down) as SVG to FILE (never half-written)")
        ->check(kNotEmpty);
    CLI::Option* watchFlag = cmd->add_flag("--watch", args->watch,
                                           "Recompile whenever GRAPH is saved and print the text plan's diff (until Ctrl-C)");
    cmd->add_option("--watch-interval-ms", args->watchIntervalMs, "How often --watch looks at GRAPH")
        ->check(CLI::Range(10u, 60000u))
        ->needs(watchFlag);
    cmd->add_option("--watch-iterations", args->watchIterations,
                    "Stop --watch after this many recompilations (0: never; for scripts and tests)")
        ->needs(watchFlag);
    return {cmd, [args] { return run(*args); }};
}

}  // namespace skygraph::cli
