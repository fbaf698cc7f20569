// `skygraph check`: compile, compare with the golden, verify, run; case by case.
#include "check.hpp"

#include "presented_images.hpp"
#include "printable_name.hpp"
#include "render.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/feature_combinations.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/verifier.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

namespace skygraph::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr size_t kKeptMessages = 5;
constexpr size_t kAllUpTo = 8;  // features; beyond, FeatureCoverage::Automatic checks pairwise

std::string describe(const FeatureValues& features, const GraphDesc& graph) {
    std::string text;
    const auto add = [&](const std::string& name, bool on) {
        text += (text.empty() ? "" : " ") + name + (on ? "=on" : "=off");
    };
    for (const FeatureDecl& f : graph.features) {
        const auto it = features.find(f.name);
        add(f.name, it != features.end() ? it->second : f.defaultValue);
    }
    // A name the graph does not declare is why its case fails: the row shows what was asked.
    for (const auto& asked : features)  // not a structured binding: clang 14 cannot capture one
        if (std::none_of(graph.features.begin(), graph.features.end(),
                         [&](const FeatureDecl& f) { return f.name == asked.first; }))
            add(printableName(asked.first), asked.second);
    return text.empty() ? "defaults" : text;
}

std::vector<FeatureValues> combinations(const GraphDesc& graph, const CheckOptions& options) {
    switch (options.coverage) {
        case FeatureCoverage::All: return allFeatureCombinations(graph);
        case FeatureCoverage::Pairwise: return pairwiseFeatureCombinations(graph);
        case FeatureCoverage::Given: {
            FeatureValues values = graph.defaultFeatures();
            for (const auto& [name, on] : options.features) values[name] = on;
            return {values};
        }
        case FeatureCoverage::Automatic: break;
    }
    return graph.features.size() <= kAllUpTo ? allFeatureCombinations(graph) : pairwiseFeatureCombinations(graph);
}

std::string errorText(const std::exception& e) {
    if (const auto* g = dynamic_cast<const GraphError*>(&e)) return g->diagnostics().format();
    return e.what();
}

size_t barrierCount(const Plan& plan) {
    size_t n = plan.finalBarriers().size() + plan.inPassBarriers().size();
    for (const PlannedPass& p : plan.passes()) n += p.barriers.size();
    return n;
}

/// The golden file of case `c`: goldenFileName(), with the layouts policy in it when --layouts
/// overrides the graph's (so that --update under one policy never overwrites the other's).
fs::path goldenOf(const CheckCase& c, const GraphDesc& graph, const CheckOptions& options) {
    std::string name = goldenFileName(graph, c.features);
    if (options.layouts) {
        constexpr std::string_view kSuffix = ".plan.txt";
        name.insert(name.size() - kSuffix.size(), ".layouts-" + std::string(toString(*options.layouts)));
    }
    return *options.goldenDir / name;
}

/// Compile, golden and verifier: device-free, so cases run on several threads.
void compileAndCompare(CheckCase& c, const GraphDesc& graph, const PassRegistry& registry,
                       const CheckOptions& options) {
    CompileOptions co;
    co.features = c.features;
    co.outputWidth = options.planWidth;
    co.outputHeight = options.planHeight;
    co.layouts = options.layouts;
    Plan plan;
    try {
        plan = compile(graph, co);
    } catch (const std::exception& e) {
        c.compileError = errorText(e);
        return;
    }
    // What a pass type refuses of its passes as this plan runs them, a renderer would refuse.
    if (const Diagnostics problems = plannedPassProblems(plan, graph, registry); !problems.empty()) {
        c.compileError = problems.format();
        return;
    }
    c.passes = plan.passes().size();
    c.culled = plan.culled().size();
    c.barriers = barrierCount(plan);
    c.presentsNothing = presentsNothing(plan, graph);
    const verifier::VerificationReport report = verifier::verifyPlan(plan, graph);
    c.verifierFindings = report.findings.size();
    for (const verifier::Finding& f : report.findings) c.verifierReport += verifier::format(f) + "\n";
    if (!options.goldenDir) return;
    const fs::path golden = goldenOf(c, graph, options);
    if (!options.updateGoldens) {
        c.golden = compareWithGolden(plan, golden);
        return;
    }
    // A plan the verifier faults is no golden to review: it stays unwritten.
    GoldenComparison unwritten;
    unwritten.status = GoldenStatus::Unwritable;
    unwritten.file = golden;
    if (c.verifierFindings) {
        unwritten.message = "not written: the plan verifier found problems in this plan";
        c.golden = unwritten;
        return;
    }
    try {
        writeGolden(plan, golden);
        c.goldenWritten = true;
    } catch (const std::exception& e) {
        unwritten.message = e.what();
        c.golden = unwritten;
    }
}

/// Runs the case on `device` as `skygraph render` would, headless, with validation counting.
void runOnDevice(CheckCase& c, Device& device, const CheckOptions& options) {
    RenderOptions ro;
    ro.graph = c.file;
    ro.sceneText = options.sceneText;
    ro.features = c.features;
    ro.width = options.runWidth;
    ro.height = options.runHeight;
    ro.frames = options.frames;
    ro.framesInFlight = options.framesInFlight;
    ro.validate = true;
    ro.passes = options.passes;
    device.clearMessages();
    try {
        FrameInputs inputs = loadFrameInputs(ro);
        CompileOptions co = inputs.compile;
        co.presentReplacement = ExternalState::TransferSrc;
        co.layouts = options.layouts;
        const RenderedFrames frames = renderFrames(device, CompiledGraph(inputs.graph, co), inputs, ro);
        c.ran = true;
    } catch (const std::exception& e) {
        c.runError = errorText(e);
    }
    c.validationMessages = device.messageCount();
    c.performanceWarnings = device.performanceWarningCount();
    for (const std::vector<ValidationMessage>& list : {device.messages(), device.performanceWarnings()})
        for (const ValidationMessage& m : list)
            if (c.messages.size() < kKeptMessages) {
                // The layer's text repeats the id and handles before " | "; the sentence is last.
                const size_t bar = m.message.rfind(" | ");
                c.messages.push_back(m.idName + ": " + (bar == std::string::npos ? m.message : m.message.substr(bar + 3)));
            }
    device.clearMessages();
}

}  // namespace

bool CheckCase::failed(bool warningsAsErrors) const { return !failures(warningsAsErrors).empty(); }

std::vector<std::string> CheckCase::failures(bool warningsAsErrors) const {
    std::vector<std::string> out;
    if (!compileError.empty()) out.push_back("does not compile: " + compileError);
    if (!notChecked.empty()) out.push_back("not checked: " + notChecked);
    if (golden && !golden->ok()) out.push_back("golden " + std::string(toString(golden->status)) + ": " + golden->message);
    if (verifierFindings) out.push_back(std::to_string(verifierFindings) + " plan verifier finding(s)");
    if (!presentsNothing.empty()) out.push_back("presents nothing: " + presentsNothing);
    if (!runError.empty()) out.push_back("cannot run: " + runError);
    if (validationMessages) out.push_back(std::to_string(validationMessages) + " validation message(s)");
    if (warningsAsErrors && performanceWarnings)
        out.push_back(std::to_string(performanceWarnings) + " performance warning(s), errors by --warnings-as-errors");
    return out;
}

std::vector<CheckCase> runCheck(const CheckOptions& options) {
    const PassRegistry registry = options.passes ? options.passes->registry() : PassRegistry::withBuiltins();
    std::vector<CheckCase> cases;
    std::vector<std::shared_ptr<const GraphDesc>> graphOf;  // per case; null when it did not load
    for (const fs::path& file : options.graphs) {
        std::shared_ptr<const GraphDesc> graph;
        std::vector<FeatureValues> chosen;
        try {
            graph = std::make_shared<const GraphDesc>(loadGraphFile(file, registry));
            chosen = combinations(*graph, options);
        } catch (const std::exception& e) {
            CheckCase& c = cases.emplace_back();
            c.file = file;
            c.combination = "-";
            // A graph that loaded but whose combinations are too many to list was not compiled.
            (graph ? c.notChecked : c.compileError) = errorText(e);
            graphOf.push_back(nullptr);
            continue;
        }
        for (FeatureValues& values : chosen) {
            CheckCase& c = cases.emplace_back();
            c.file = file;
            c.combination = describe(values, *graph);
            c.features = std::move(values);
            graphOf.push_back(graph);
        }
    }
    // Two cases with one golden file (the same graph twice, two graphs of one file name, or
    // names that meet: a.json's feature b on and a.b-on.json) would overwrite or compare
    // against each other's: the later ones fail instead.
    if (options.goldenDir) {
        std::map<fs::path, size_t> firstWith;
        for (size_t i = 0; i < cases.size(); ++i) {
            if (!graphOf[i]) continue;
            const fs::path golden = goldenOf(cases[i], *graphOf[i], options);
            const auto [it, fresh] = firstWith.emplace(golden, i);
            if (fresh) continue;
            const fs::path& first = cases[it->second].file;
            const fs::path& second = cases[i].file;
            std::error_code ec;
            const bool sameFile = first == second || fs::equivalent(first, second, ec);
            std::string why;
            if (sameFile) why = "the file is named twice";
            else if (first.stem() == second.stem())
                why = "check graphs of one file name with different --golden directories";
            else
                why = "the golden names of " + first.string() + " and " + second.string() +
                      " collide (a file name and features spell the other's); check them with different --golden "
                      "directories or rename one";
            cases[i].notChecked = "its golden " + golden.string() + " is also " + first.string() + "'s: " + why;
            graphOf[i] = nullptr;
        }
    }
    const size_t total = cases.size();
    std::atomic<size_t> next{0};
    std::vector<double> compileSeconds(total, 0.0);
    const auto work = [&] {
        for (size_t i = next++; i < total; i = next++) {
            if (!graphOf[i]) continue;
            const auto start = Clock::now();
            try {
                compileAndCompare(cases[i], *graphOf[i], registry, options);
            } catch (const std::exception& e) {  // out of memory, say: this case fails, the rest go on
                cases[i].notChecked = e.what();
            }
            compileSeconds[i] = std::chrono::duration<double>(Clock::now() - start).count();
        }
    };
    std::vector<std::jthread> threads;
    for (unsigned t = 1; t < std::max(1u, options.jobs); ++t) threads.emplace_back(work);
    work();
    threads.clear();

    std::unique_ptr<Device> device;
    std::string deviceError;
    for (size_t i = 0; i < total; ++i) {
        CheckCase& c = cases[i];
        c.seconds = compileSeconds[i];
        if (options.run && graphOf[i] && c.compiled()) {
            c.runAttempted = true;
            const auto start = Clock::now();
            if (!device && deviceError.empty()) {
                try {
                    DeviceOptions dopts;
                    dopts.device = options.device;
                    dopts.validation = true;
                    dopts.logMessages = false;  // counted and reported per case instead
                    device = Device::create(dopts);
                } catch (const std::exception& e) {
                    deviceError = std::string("no device: ") + e.what();
                }
            }
            if (device) {
                runOnDevice(c, *device, options);
                // A run that threw may have lost the device: the next case gets a fresh one.
                if (!c.runError.empty()) device.reset();
            } else {
                c.runError = deviceError;
            }
            c.seconds += std::chrono::duration<double>(Clock::now() - start).count();
        }
        if (options.onCaseDone) options.onCaseDone(i + 1, total);
    }
    return cases;
}

}  // namespace skygraph::app
