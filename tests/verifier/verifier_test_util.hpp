// What the verifier's tests and its bulk runner share: loading graphs, the shipped graphs
// and their feature combinations, and verifying one random graph.
#pragma once

#include <skygraph/verifier.hpp>

#include <skygraph/compiler.hpp>
#include <skygraph/pass_registry.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph::test {

/// The built-in pass types (Generic among them).
[[nodiscard]] const PassRegistry& registry();

/// graphs/*.json.
[[nodiscard]] std::vector<std::filesystem::path> shippedGraphs();

/// Every combination of the graph's features.
[[nodiscard]] std::vector<FeatureValues> featureCombinations(const GraphDesc& graph);

/// `co` made headless: Present targets become TransferSrc and are read back after the frame.
[[nodiscard]] CompileOptions headless(const GraphDesc& graph, CompileOptions co);

/// Each finding on a line of its own.
[[nodiscard]] std::string describe(const std::vector<verifier::Finding>& findings);

/// One plan of a random graph with findings (or that did not compile).
struct RandomFailure {
    uint32_t seed = 0;
    std::string variant;  ///< "presenting", "headless, first-use placement", "reordered"
    std::string detail;   ///< The report's summary or the compile error.
    std::string json;     ///< The graph.
};

struct RandomResult {
    uint32_t plans = 0;                           ///< Plans compiled and verified.
    uint32_t aliasingPlans = 0;                   ///< Those in which a resource takes over another's memory.
    uint32_t findings = 0;                        ///< Findings over all of them.
    uint32_t compileErrors = 0;                   ///< Graphs the compiler rejected (the generator promises none).
    std::vector<RandomFailure> failures;
};

/// Random graph `seed` (tests/executor/random_graph_generator.hpp) compiled with aliasing on:
/// with chains of short-lived transients, buffers among them (headless for even seeds, frames
/// sharing the heaps for odd ones, clobbered for every third); presenting with best-fit placement; headless with first-use
/// placement and a read-back, clobbering transients for odd seeds; and every fourth seed also
/// with its passes reordered. Adds to `result`.
void verifyRandomGraph(uint32_t seed, RandomResult& result);

}  // namespace skygraph::test

namespace skygraph::test {

/// A graph and a plan compiled from it.
struct Compiled {
    GraphDesc graph;
    Plan plan;
};
/// Parses `json` (a graph file's text) and compiles it; the output is 16x16 unless `options`
/// says otherwise.
/// Options for a fixture: one frame's aliasing alone, each frame in flight with heaps of its
/// own (the frames-sharing-heaps case has tests of its own).
[[nodiscard]] inline CompileOptions perFrameHeaps() {
    CompileOptions o;
    o.shareTransientsAcrossFrames = false;
    return o;
}
[[nodiscard]] Compiled compileText(const std::string& json, CompileOptions options = perFrameHeaps());
/// Loads graphs/NAME and compiles it.
[[nodiscard]] Compiled compileShipped(const std::string& name, CompileOptions options = {});
/// The index of the step called `name`; throws std::out_of_range when there is none.
[[nodiscard]] size_t stepIndex(const Plan& plan, std::string_view name);
/// The submit that holds step `step`; throws std::out_of_range when none does.
[[nodiscard]] size_t submitOf(const Plan& plan, size_t step);
/// The index into `plan.passes()[step].barriers` of the first barrier on resource `resource`;
/// throws std::out_of_range when there is none.
[[nodiscard]] size_t barrierOn(const Plan& plan, size_t step, std::string_view resource);
/// The index of the first usage of `resource` in step `step`; throws std::out_of_range.
[[nodiscard]] size_t usageOf(const Plan& plan, size_t step, std::string_view resource);
/// Whether `report` has a finding of `kind` naming `resource` (any resource when empty).
[[nodiscard]] bool hasFinding(const verifier::VerificationReport& report, verifier::FindingKind kind,
                              std::string_view resource = {});

}  // namespace skygraph::test
