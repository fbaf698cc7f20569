// Running generated graphs, and weakening their barriers one at a time for the oracle.
#include "random_graph_check.hpp"

#include "compiled_graph_access.hpp"
#include "generic_passes.hpp"
#include "headless_options.hpp"
#include "plan_editor.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/verifier.hpp>

#include <bit>
#include <span>
#include <stdexcept>
#include <string>

namespace skygraph::test {
namespace {

std::string formatMessages(const Device& d) {
    std::string s;
    for (const auto& m : d.messages()) s += "  [" + m.idName + "] " + m.message + "\n";
    return s;
}

void renderFrames(Device& device, CompiledGraph compiled, const RunSettings& settings) {
    Renderer r(device, std::move(compiled), genericOptions(settings.framesInFlight));
    for (uint32_t i = 0; i < settings.frames; ++i) r.renderFrame();
    (void)r.readback();
    r.waitIdle();
}

/// Each set bit of `mask` cleared in turn.
template <class F>
void forEachBit(uint64_t mask, F&& f) {
    while (mask) {
        const uint64_t bit = mask & (~mask + 1);
        f(bit);
        mask &= ~bit;
    }
}

std::string nameOf(const Plan& plan, const Barrier& b) {
    if (b.resource >= plan.resources().size()) throw std::out_of_range("a barrier of no plan resource");
    return std::string(plan.resources()[b.resource].name);
}

/// Adds every weakening of `list[i]` (list is a barrier batch of `base`; `locate` finds the
/// same batch in a copy, editable, and `drop(copy, i)` removes its barrier i).
template <class Locate, class Drop>
void weakenBatch(const Plan& base, std::span<const Barrier> list, const std::string& where,
                 Locate locate, Drop drop, std::vector<BarrierMutation>& out) {
    for (size_t i = 0; i < list.size(); ++i) {
        const Barrier& b = list[i];
        const char* kind = b.kind == BarrierKind::Image ? "image" : b.kind == BarrierKind::Buffer ? "buffer" : "memory";
        const std::string what = where + ", " + nameOf(base, b) + " (" + kind + "): ";
        {
            Plan p = base;
            drop(p, i);
            out.push_back({what + "barrier dropped", std::move(p)});
        }
        auto mutate = [&](const std::string& how, auto change) {
            Plan p = base;
            change(locate(p)[i]);
            out.push_back({what + how, std::move(p)});
        };
        // An aliasing barrier's source scope is what it waits for of the other resources whose
        // memory it takes over: their last uses, on images described differently, whose hazards
        // the validation layer cannot see through the shared memory. Narrowing it is the plan
        // verifier's to catch (tests/verifier has the negative controls), not this oracle's;
        // the barrier's layout transition and destination stay here.
        const bool layerSeesSource = !b.aliasing;
        if (layerSeesSource) forEachBit(b.srcStages, [&](uint64_t bit) {
            mutate("src stage " + stageMaskNames(bit).front() + " dropped", [&](Barrier& x) { x.srcStages &= ~bit; });
        });
        forEachBit(b.dstStages, [&](uint64_t bit) {
            mutate("dst stage " + stageMaskNames(bit).front() + " dropped", [&](Barrier& x) { x.dstStages &= ~bit; });
        });
        if (layerSeesSource) forEachBit(b.srcAccess, [&](uint64_t bit) {
            mutate("src access " + accessMaskNames(bit).front() + " dropped", [&](Barrier& x) { x.srcAccess &= ~bit; });
        });
        forEachBit(b.dstAccess, [&](uint64_t bit) {
            mutate("dst access " + accessMaskNames(bit).front() + " dropped", [&](Barrier& x) { x.dstAccess &= ~bit; });
        });
        if (b.kind == BarrierKind::Image && b.oldLayout != b.newLayout &&
            b.oldLayout != VK_IMAGE_LAYOUT_UNDEFINED)
            mutate("layout change dropped", [&](Barrier& x) { x.newLayout = x.oldLayout; });
    }
}

}  // namespace

RunSettings settingsForSeed(uint32_t seed) {
    RunSettings settings;
    if (seed % 2 == 1) settings.layouts = LayoutPolicy::Optimal;
    return settings;
}

GraphRun runGraph(Device& device, const std::string& json, const FeatureValues& features,
                  const RunSettings& settings) {
    GraphRun run;
    try {
        GraphDesc graph = parseGraph(json, "<random>", PassRegistry::withBuiltins());
        CompileOptions o = sizedOptions(settings.size, settings.size);
        o.features = features;
        o.layouts = settings.layouts;
        // The renderer runs plans placed with its device's memory requirements (it compiles
        // others again), and the oracle's weakened copies must be of the plan that runs.
        o.memory = device.memoryModel();
        o.queueFamilies = device.queueFamilies();
        o = headless(graph, std::move(o));
        run.compiled.emplace(std::move(graph), std::move(o));
    } catch (const GraphError& e) {
        run.outcome = GraphRun::Outcome::Rejected;
        run.detail = e.diagnostics().format();
        return run;
    }
    device.clearMessages();
    try {
        renderFrames(device, *run.compiled, settings);
    } catch (const std::exception& e) {
        run.outcome = GraphRun::Outcome::ExecutorFailed;
        run.detail = e.what();
        return run;
    }
    if (device.messageCount() != 0) {
        run.outcome = GraphRun::Outcome::Messages;
        run.detail = formatMessages(device) + planToText(run.compiled->plan());
    }
    device.clearMessages();
    return run;
}

uint32_t messagesFor(Device& device, const CompiledGraph& compiled, const Plan& plan, const RunSettings& settings) {
    device.clearMessages();
    renderFrames(device, detail::CompiledGraphAccess::withPlan(compiled, plan), settings);
    const uint32_t n = device.messageCount();
    device.clearMessages();
    return n;
}

std::vector<BarrierMutation> weakenedPlans(const Plan& plan) {
    std::vector<BarrierMutation> out;
    for (size_t p = 0; p < plan.passes().size(); ++p)
        weakenBatch(plan, plan.passes()[p].barriers, "before " + std::string(plan.passes()[p].name),
                    [p](Plan& x) { return detail::PlanEditor::barriersOf(x, p); },
                    [p](Plan& x, size_t i) { detail::PlanEditor::eraseBarrier(x, p, i); }, out);
    weakenBatch(
        plan, plan.finalBarriers(), "final",
        [](Plan& x) { return std::span<Barrier>(detail::PlanEditor::finalBarriers(x)); },
        [](Plan& x, size_t i) {
            std::vector<Barrier>& final = detail::PlanEditor::finalBarriers(x);
            final.erase(final.begin() + static_cast<std::ptrdiff_t>(i));
        },
        out);
    return out;
}

MinimalityReport checkMinimality(Device& device, const CompiledGraph& compiled, const RunSettings& settings) {
    MinimalityReport report;
    report.planVerifies = verifier::verifyPlan(compiled.plan(), compiled.graph()).ok();
    for (auto& m : weakenedPlans(compiled.plan())) {
        ++report.mutations;
        if (messagesFor(device, compiled, m.plan, settings) == 0)
            report.unneeded.push_back({m.description, !verifier::verifyPlan(m.plan, compiled.graph()).ok()});
    }
    return report;
}

}  // namespace skygraph::test
