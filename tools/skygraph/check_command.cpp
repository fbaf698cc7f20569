#include "check_command.hpp"

#include "builtin_defaults.hpp"
#include "printable_name.hpp"
#include "progress_bar.hpp"
#include "replace_file.hpp"

#include "app/check.hpp"
#include "app/check_report.hpp"

#include <skygraph/pass.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

namespace skygraph::cli {
namespace {

struct CheckArgs {
    app::CheckOptions options;
    std::vector<std::string> graphs;
    std::string golden, features = "auto", size = "64x64", junit, layouts;
    bool warningsAsErrors = false, noRun = false;
};

/// --features: auto, all, pairwise, or NAME=on,NAME=off (one combination).
void parseCoverage(const std::string& text, app::CheckOptions& o) {
    if (text == "auto") o.coverage = app::FeatureCoverage::Automatic;
    else if (text == "all") o.coverage = app::FeatureCoverage::All;
    else if (text == "pairwise") o.coverage = app::FeatureCoverage::Pairwise;
    else {
        std::vector<std::string> flags;
        for (size_t start = 0;;) {
            const size_t comma = text.find(',', start);
            flags.push_back(text.substr(start, comma - start));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        // A comma at either end or two together: a feature was meant there and got lost.
        if (std::any_of(flags.begin(), flags.end(), [](const std::string& f) { return f.empty(); }))
            throw UsageError("--features '" + printableName(text) +
                             "' has an empty element; expected NAME=on,NAME=off,... with no comma at either end or two "
                             "together");
        o.coverage = app::FeatureCoverage::Given;
        o.features = parseFeatureFlags(flags, "--features");
    }
}

/// --size WIDTHxHEIGHT, each side a number as --width takes one: " 64" and "+64" are not.
void parseSize(const std::string& text, app::CheckOptions& o) {
    const std::string expected = "expected WIDTHxHEIGHT, each 1 to 16384 (e.g. 64x64)";
    const size_t x = text.find('x');
    if (x == std::string::npos)
        throw UsageError("--size '" + printableName(text) + "': " + expected);
    uint32_t sides[2] = {};
    for (int i = 0; i < 2; ++i) {
        std::string side = i == 0 ? text.substr(0, x) : text.substr(x + 1);
        if (const std::string why = whyNotANumber(side, true); !why.empty())
            throw UsageError("--size '" + printableName(text) + "': " + printableName(why) + "; " + expected);
        const auto [end, error] = std::from_chars(side.data(), side.data() + side.size(), sides[i]);
        if (error != std::errc() || end != side.data() + side.size() || sides[i] == 0 || sides[i] > 16384)
            throw UsageError("--size '" + printableName(text) + "': " + expected);
    }
    o.runWidth = sides[0];
    o.runHeight = sides[1];
}

/// The goldens' folder holds golden plans only: a report written there would replace the
/// golden of its name (or stand among them as one), and a check would not see that.
void refuseJUnitAmongGoldens(const std::string& junit, const std::filesystem::path& golden) {
    if (junit.empty() || golden.empty()) return;
    std::error_code ec;
    const std::filesystem::path folder = std::filesystem::weakly_canonical(std::filesystem::absolute(golden, ec), ec);
    const std::filesystem::path report = files::landingPath(junit);
    if (!ec && !report.empty() && report.parent_path() == folder)
        throw UsageError("--junit '" + printableName(junit) + "' is in the --golden folder '" +
                         printableName(golden.string()) + "', which holds golden plans only");
}

int run(CheckArgs& args) {
    static const PassLibrary library = PassLibrary::withBuiltins();
    app::CheckOptions o = args.options;
    for (const std::string& g : args.graphs) o.graphs.emplace_back(g);
    refuseToOverwriteInputs("--junit", args.junit, o.graphs);
    if (!args.junit.empty()) requireWritableOutput(args.junit);  // before the cases run
    if (!args.golden.empty()) {
        // A missing folder fails each case with a line that says so; a file there is a mistake
        // in the command line, named once instead of as a missing golden inside it per case.
        std::error_code ec;
        if (std::filesystem::exists(args.golden, ec) && !std::filesystem::is_directory(args.golden, ec))
            throw std::runtime_error("--golden '" + printableName(args.golden) + "' is not a folder");
        o.goldenDir = args.golden;
        refuseJUnitAmongGoldens(args.junit, args.golden);
    }
    if (o.updateGoldens && !o.goldenDir) throw UsageError("--update needs --golden DIR");
    parseCoverage(args.features, o);
    parseSize(args.size, o);
    o.layouts = parseLayoutsFlag(args.layouts);
    o.run = !args.noRun;
    o.passes = &library;
    o.sceneText = kDefaultScene;
    // Each run would log how the scene sets features; the table says what matters (-v shows it).
    if (spdlog::get_level() == spdlog::level::info) spdlog::set_level(spdlog::level::warn);
    std::optional<ProgressBar> bar;
    o.onCaseDone = [&](size_t done, size_t total) {
        if (!bar) bar.emplace("check", total, "cases");
        bar->advance(done - bar->done());
        if (done == total) bar->finish();
    };
    const std::vector<app::CheckCase> cases = app::runCheck(o);
    if (bar) bar->finish();
    std::cout << app::checkTable(cases, args.warningsAsErrors) << std::flush;
    if (!args.junit.empty()) writeOutput(args.junit, app::checkJUnit(cases, args.warningsAsErrors));
    for (const app::CheckCase& c : cases)
        if (c.failed(args.warningsAsErrors)) return kExitUserError;
    return kExitOk;
}

}  // namespace

Command addCheckCommand(CLI::App& parent) {
    auto args = std::make_shared<CheckArgs>();
    app::CheckOptions& o = args->options;
    CLI::App* cmd = parent.add_subcommand(
        "check", "Check graphs under every feature combination: compile, compare with reviewed golden plans, verify "
                 "with the plan verifier, and run under validation with synchronization validation. Exit 0 only "
                 "when every case passes");
    cmd->add_option("graphs", args->graphs, "Graph files")->required()->check(kNotEmpty);
    cmd->add_option("--golden", args->golden,
                    "Directory of golden plans (<graph>.<feature>-on|off....plan.txt) to compare with")
        ->check(kNotEmpty);
    cmd->add_flag("--update", o.updateGoldens, "Write the golden plans instead of comparing (then review them)");
    cmd->add_option("--features", args->features,
                    "Which combinations: auto (all up to 8 features, else pairwise; the default), all, pairwise, "
                    "or one: NAME=on,NAME=off,... (the others at their defaults)")
        ->check(kNotEmpty);
    cmd->add_option("--layouts", args->layouts,
                    "Compile and run with this layout policy (fewest-barriers, optimal) instead of the graph's")
        ->check(CLI::IsMember({"fewest-barriers", "optimal"}));
    cmd->add_option("--frames", o.frames, "Frames to run each combination")
        ->check(CLI::Range(1u, 1000u))->capture_default_str();
    cmd->add_option("--frames-in-flight", o.framesInFlight, "Frames in flight")
        ->check(CLI::Range(1u, 8u))->capture_default_str();
    cmd->add_option("--size", args->size, "Output size of the runs, WIDTHxHEIGHT (goldens and the verifier use "
                                          "1920x1080)");
    cmd->add_option("--device", o.device, "Device by index or name (default: a GPU, else lavapipe)")->check(kNotEmpty);
    cmd->add_flag("--no-run", args->noRun, "Compile, compare and verify only; no device");
    cmd->add_option("--junit", args->junit, "Also write JUnit XML to FILE (never half-written)")->check(kNotEmpty);
    cmd->add_option("--jobs", o.jobs, "Threads that compile, compare and verify (runs take turns on one device)")
        ->check(CLI::Range(1u, 256u));
    cmd->add_flag("--warnings-as-errors", args->warningsAsErrors, "Fail cases with validation performance warnings");
    return {cmd, [args] { return run(*args); }};
}

}  // namespace skygraph::cli
