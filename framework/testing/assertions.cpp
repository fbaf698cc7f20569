#include <skygraph/golden.hpp>
#include <skygraph/testing/assertions.hpp>
#include <skygraph/verifier.hpp>

#include <cstdlib>
#include <string_view>

namespace skygraph::testkit {

::testing::AssertionResult matchesGolden(const Plan& plan, const std::filesystem::path& golden) {
    if (const char* update = std::getenv("SKYGRAPH_UPDATE_GOLDEN"); update && std::string_view(update) == "1") {
        try {
            writeGolden(plan, golden);
        } catch (const std::exception& e) {
            return ::testing::AssertionFailure() << e.what();
        }
        return ::testing::AssertionSuccess() << "wrote " << golden.string() << ": review it";
    }
    const GoldenComparison c = compareWithGolden(plan, golden);
    if (c.ok()) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "golden " << toString(c.status) << ": " << c.message << "\n" << c.diff;
}

::testing::AssertionResult verifies(const Plan& plan, const GraphDesc& graph) {
    const verifier::VerificationReport report = verifier::verifyPlan(plan, graph);
    if (report.ok()) return ::testing::AssertionSuccess();
    ::testing::AssertionResult failure = ::testing::AssertionFailure();
    failure << "the plan verifier found " << report.findings.size() << " problem(s) in graph '" << graph.name << "':";
    for (const verifier::Finding& f : report.findings) failure << "\n  " << verifier::format(f);
    return failure;
}

}  // namespace skygraph::testkit
