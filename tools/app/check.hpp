// `skygraph check`: a graph file under each combination of its features, compiled and compared
// with its reviewed golden plan, verified by the plan verifier, and run for a few frames under
// validation. Application code: the command line links it, and so do its tests.
#pragma once

#include <skygraph/compiler.hpp>
#include <skygraph/condition.hpp>
#include <skygraph/golden.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace skygraph {
class PassLibrary;
}

namespace skygraph::app {

/// Which feature combinations of each graph are checked.
enum class FeatureCoverage : uint8_t {
    Automatic,  ///< All of them up to 8 features (256 combinations), pairwise beyond.
    All,        ///< Every combination (at most 16 features).
    Pairwise,   ///< A set covering every pair of features with each pair of values.
    Given,      ///< One combination: the graph's defaults with CheckOptions::features.
};

/// What `check` does. A plain value; it borrows `passes`.
struct CheckOptions {
    std::vector<std::filesystem::path> graphs;
    /// Where the goldens are (goldenFileName()); unset: no golden comparison.
    std::optional<std::filesystem::path> goldenDir;
    bool updateGoldens = false;  ///< Write the goldens instead of comparing.
    FeatureCoverage coverage = FeatureCoverage::Automatic;
    FeatureValues features;  ///< For FeatureCoverage::Given.
    /// Goldens and verification use the plan at this size (what a reviewer reads)...
    uint32_t planWidth = 1920, planHeight = 1080;
    /// ...runs use a small one.
    uint32_t runWidth = 64, runHeight = 64;
    uint32_t frames = 3;
    uint32_t framesInFlight = 2;
    bool run = true;  ///< false: compile, compare and verify only (no device).
    std::string device;
    std::string sceneText;  ///< The scene the runs use (the passes' inputs); empty: none.
    std::optional<LayoutPolicy> layouts;  ///< Unset: each graph's own setting.
    /// Threads that compile, compare and verify; runs share one device, one at a time.
    unsigned jobs = 1;
    const PassLibrary* passes = nullptr;  ///< Recording code; null: every pass Generic.
    /// Called after each case is done, with (cases done, cases in all). May be empty.
    std::function<void(size_t done, size_t total)> onCaseDone;
};

/// One graph under one feature combination.
struct CheckCase {
    std::filesystem::path file;  ///< As the command line named it: what the report shows.
    FeatureValues features;
    /// "skybox=on ui=off" (with any feature asked for that the graph does not declare), or
    /// "defaults" for a graph without features.
    std::string combination;
    std::string compileError; ///< Why it did not load or compile; empty when it compiled.
    /// Why a graph that loaded was not compiled at all (too many features for every
    /// combination, a golden another case has); empty when it was.
    std::string notChecked;
    size_t passes = 0, culled = 0, barriers = 0;
    std::optional<GoldenComparison> golden;  ///< Unset without --golden.
    bool goldenWritten = false;
    size_t verifierFindings = 0;
    std::string verifierReport;  ///< One line per finding.
    std::string presentsNothing;  ///< presentsNothing()'s answer for its plan (presented_images.hpp).
    bool runAttempted = false;  ///< A run was tried (it may have failed: runError).
    bool ran = false;           ///< It rendered every frame.
    std::string runError;  ///< The device could not run it.
    uint32_t validationMessages = 0, performanceWarnings = 0;
    std::vector<std::string> messages;  ///< The first few of either kind, one line each.
    double seconds = 0;

    /// Whether a plan was compiled, so that its counts and verifier findings mean something.
    [[nodiscard]] bool compiled() const { return compileError.empty() && notChecked.empty(); }
    /// Whether this case fails the check: any error, finding, message or golden difference
    /// (and, with `warningsAsErrors`, performance warnings).
    [[nodiscard]] bool failed(bool warningsAsErrors) const;
    /// The reasons it fails, one line each; empty when it passes.
    [[nodiscard]] std::vector<std::string> failures(bool warningsAsErrors) const;
};

/// Every case, graph by graph and combination by combination. Never throws for bad graphs,
/// goldens or devices: each case says what went wrong, and the others still run.
[[nodiscard]] std::vector<CheckCase> runCheck(const CheckOptions& options);

}  // namespace skygraph::app
