// GoogleTest assertions for an embedder's own graphs (library skygraph::testing, which links
// GoogleTest): a plan against its reviewed golden file, a plan through the plan verifier, and a
// graph rendered under validation. Each returns an AssertionResult whose message says what
// failed, for EXPECT_TRUE / ASSERT_TRUE:
//
//     EXPECT_TRUE(skygraph::testkit::matchesGolden(plan, "golden/" + goldenFileName(graph, features)));
//     EXPECT_TRUE(skygraph::testkit::verifies(plan, graph));
//     EXPECT_TRUE(skygraph::testkit::rendersWithoutValidationMessages(*device, compiled, rendererOptions));
#pragma once

#include <skygraph/compiled_graph.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>
#include <skygraph/renderer.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>

namespace skygraph {
class Device;
}

namespace skygraph::testkit {

/// Success when `plan` matches the golden file `golden` (<skygraph/golden.hpp>); otherwise the
/// status and a unified diff from the golden to the plan. With SKYGRAPH_UPDATE_GOLDEN=1 in the
/// environment it writes the golden instead and succeeds; review the written file.
[[nodiscard]] ::testing::AssertionResult matchesGolden(const Plan& plan, const std::filesystem::path& golden);

/// Success when the plan verifier (<skygraph/verifier.hpp>) finds nothing in `plan`, compiled
/// from `graph`; otherwise one line per finding.
[[nodiscard]] ::testing::AssertionResult verifies(const Plan& plan, const GraphDesc& graph);

/// Renders `frames` (at least 1) frames of `compiled` on `device`, which must have been
/// created with validation on, and waits for them; success when the validation layer counted
/// no message (performance warnings left out), otherwise the messages. The device's messages
/// are cleared first and left as the frames left them. What the renderer throws is a failure
/// too. The Renderer runs what it would run in the application: a plan compiled without the
/// device's memory model (CompileOptions::memory = device.memoryModel()) is compiled again
/// with it. Needs the executor (a package built with it).
[[nodiscard]] ::testing::AssertionResult rendersWithoutValidationMessages(Device& device, const CompiledGraph& compiled,
                                                                          const RendererOptions& options = {},
                                                                          uint32_t frames = 3);

}  // namespace skygraph::testkit
