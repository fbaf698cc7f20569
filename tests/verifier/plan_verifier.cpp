// verifyPlan: build the frame model, then run each check over it.
#include "plan_verifier.hpp"

#include "checks.hpp"
#include "frame_model.hpp"
#include "report.hpp"

namespace skygraph::verifier {

VerificationReport verifyPlan(const Plan& plan, const GraphDesc& graph, const VerifyOptions& options) {
    Reporter reporter(options.maxFindings);
    const FrameModel model = buildFrameModel(plan, graph, options, reporter);
    checkLayoutsAndContents(model, plan, graph, reporter);
    checkLiveOverlaps(model, reporter);
    const size_t pairs = checkMemoryDependencies(model, plan, reporter);
    VerificationReport report = std::move(reporter.report());
    report.accessesChecked = model.accesses.size();
    report.pairsChecked = pairs;
    return report;
}

}  // namespace skygraph::verifier
