// Runs generated graphs on a validated device: the random-graph suite's and
// tools/random-graphs.sh's one definition of "this graph passed", and the brute-force
// barrier-minimality oracle (docs/reliability.md explains the choice of oracle).
#pragma once

#include "random_graph_generator.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/device.hpp>
#include <skygraph/plan.hpp>

#include <optional>
#include <string>
#include <vector>

namespace skygraph::test {

struct RunSettings {
    uint32_t size = 16;           ///< Output width and height (the generator's outputSize).
    uint32_t frames = 2;          ///< Two frames: the second meets the first's final state.
    uint32_t framesInFlight = 1;  ///< Frame copies do not change the plan's barriers.
    /// CompileOptions::layouts; unset: the graph's (fewest barriers).
    std::optional<LayoutPolicy> layouts;
};

/// How the random-graph suites run seed `seed`: odd seeds with each reader of an image in its
/// optimal layout (transitions between reads), even ones with the fewest barriers.
[[nodiscard]] RunSettings settingsForSeed(uint32_t seed);

/// The outcome of one graph. `passed()` is the suite's verdict.
struct GraphRun {
    enum class Outcome : uint8_t { Clean, Rejected, ExecutorFailed, Messages };
    Outcome outcome = Outcome::Clean;
    std::string detail;  ///< The error or the validation messages, with the plan.
    /// The graph compiled for the run (headless, its swapchain read back); empty if Rejected.
    std::optional<CompiledGraph> compiled;
    [[nodiscard]] bool passed() const noexcept { return outcome == Outcome::Clean; }
};

/// Compiles `json` with `features` and renders it; the device's messages are cleared first.
[[nodiscard]] GraphRun runGraph(Device& device, const std::string& json, const FeatureValues& features,
                                const RunSettings& settings = {});

/// Renders `plan`, a copy of compiled.plan() (e.g. a mutated one), in place of compiled's own
/// plan and returns the message count.
[[nodiscard]] uint32_t messagesFor(Device& device, const CompiledGraph& compiled, const Plan& plan,
                                   const RunSettings& settings = {});

/// One barrier of a plan weakened one way.
struct BarrierMutation {
    std::string description;  ///< e.g. "before p2: drop barrier for img0"
    Plan plan;
};

/// Every way to weaken one barrier of `plan`: drop it; clear one source or destination
/// stage bit; clear one source or destination access bit (not the source scope of an
/// aliasing barrier, whose hazards are between differently described images sharing memory,
/// which the layer cannot see: the plan verifier's); keep the layout (newLayout = oldLayout)
/// where it changes. Each must cause a validation message if the plan is minimal.
[[nodiscard]] std::vector<BarrierMutation> weakenedPlans(const Plan& plan);

/// A mutation that produced no message.
struct UnnoticedWeakening {
    std::string description;
    /// Whether the plan verifier finds the weakened plan wrong: the oracle where the layer is
    /// blind (a storage write after a storage write between dispatches, docs/verifier.md).
    bool verifierFinds = false;
};
/// The mutations that produced no message: barriers (or bits of them) that are not needed,
/// as far as the validation layer sees real accesses of the Generic pass.
struct MinimalityReport {
    size_t mutations = 0;
    /// Whether the plan verifier passes the plan as compiled: only then does its finding on a
    /// weakened plan come from the weakening.
    bool planVerifies = false;
    std::vector<UnnoticedWeakening> unneeded;
};
[[nodiscard]] MinimalityReport checkMinimality(Device& device, const CompiledGraph& compiled,
                                               const RunSettings& settings = {});

}  // namespace skygraph::test
