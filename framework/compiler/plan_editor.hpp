// Test-only: weakens a plan on purpose, for negative controls (a dropped or narrowed barrier
// that synchronization validation or the plan verifier must catch). Plans are read-only to
// everyone else (include/skygraph/plan.hpp); this header is not installed, and only test and
// benchmark targets have framework/compiler on their include path.
//
// Every edit keeps each pass's spans viewing the plan's own barrier array (plan_builder.hpp),
// so that copying the edited plan rebases them as it does for a compiled one.
#pragma once

#include "plan_builder.hpp"

#include <skygraph/plan.hpp>

#include <cstddef>
#include <span>
#include <stdexcept>
#include <vector>

namespace skygraph::detail {

struct PlanEditor {
    /// Pass `pass`'s barriers, editable in place. Views `plan`'s barrier array: valid until
    /// the next eraseBarrier on `plan`, or while `plan` lives and is not assigned to
    /// otherwise. Throws std::out_of_range for no such pass.
    [[nodiscard]] static std::span<Barrier> barriersOf(Plan& plan, size_t pass) {
        const std::span<const Barrier> b = plan.passes_.at(pass).barriers;
        if (b.empty()) return {};
        return {plan.barriers_.data() + (b.data() - plan.barriers_.data()), b.size()};
    }

    /// Removes barrier `i` of pass `pass`; the other passes' barriers stay as they are, and
    /// their spans (earlier passes' unchanged, later ones' moved down with their barriers)
    /// stay valid. Throws std::out_of_range for no such pass or barrier.
    static void eraseBarrier(Plan& plan, size_t pass, size_t i) {
        std::vector<PlannedPass>& passes = plan.passes_;
        const std::span<const Barrier> b = passes.at(pass).barriers;
        if (i >= b.size()) throw std::out_of_range("PlanEditor::eraseBarrier: no such barrier");
        const auto at = b.data() - plan.barriers_.data() + static_cast<std::ptrdiff_t>(i);
        plan.barriers_.erase(plan.barriers_.begin() + at);  // no reallocation: earlier views stay put
        passes[pass].barriers =
            b.size() == 1 ? std::span<const Barrier>{} : std::span<const Barrier>(b.data(), b.size() - 1);
        for (size_t p = pass + 1; p < passes.size(); ++p)
            if (!passes[p].barriers.empty())
                passes[p].barriers = {passes[p].barriers.data() - 1, passes[p].barriers.size()};
    }

    /// Pass `pass`'s usages, editable in place (their resource, range, layout, masks, load and
    /// store). Views `plan`'s usage array: valid while `plan` lives and is not assigned to.
    /// Throws std::out_of_range for no such pass.
    [[nodiscard]] static std::span<PlannedUsage> usagesOf(Plan& plan, size_t pass) {
        const std::span<const PlannedUsage> u = plan.passes_.at(pass).usages;
        if (u.empty()) return {};
        return {plan.usages_.data() + (u.data() - plan.usages_.data()), u.size()};
    }

    /// The barriers after the last pass, editable (no span views them: erase freely). Valid
    /// while `plan` lives and is not assigned to.
    [[nodiscard]] static std::vector<Barrier>& finalBarriers(Plan& plan) noexcept { return plan.finalBarriers_; }
    /// The in-pass barriers, editable (no span views them). Valid as finalBarriers.
    [[nodiscard]] static std::vector<InPassBarrier>& inPassBarriers(Plan& plan) noexcept { return plan.inPassBarriers_; }
    /// The resources (lifetimes, layouts, copies, placement indices), editable. Valid as
    /// finalBarriers.
    [[nodiscard]] static std::vector<PlannedResource>& resources(Plan& plan) noexcept { return plan.resources_; }
    /// The transient memory layout (heaps, placements and their aliases), editable. Valid as
    /// finalBarriers.
    [[nodiscard]] static MemoryLayout& memory(Plan& plan) noexcept { return plan.memory_; }
    /// The presentations' semaphore stages, editable. Valid as finalBarriers.
    [[nodiscard]] static std::vector<Presentation>& presentations(Plan& plan) noexcept { return plan.presentations_; }

    /// A submit as vectors, to edit freely.
    using EditableSubmit = PlanBuilder::SubmitDraft;
    /// The submits as vectors; setSubmits puts edited ones back.
    [[nodiscard]] static std::vector<EditableSubmit> submits(const Plan& plan) {
        std::vector<EditableSubmit> out;
        for (const Submit& s : plan.submits_)
            out.push_back({s.queue, {s.passes.begin(), s.passes.end()}, {s.waits.begin(), s.waits.end()},
                           {s.releases.begin(), s.releases.end()}, {s.signals.begin(), s.signals.end()},
                           s.waitsForAcquire});
        return out;
    }
    /// Replaces the plan's submits (the queue of each pass follows its submit).
    static void setSubmits(Plan& plan, const std::vector<EditableSubmit>& submits) {
        PlanBuilder::setSubmits(plan, submits);
        for (const EditableSubmit& s : submits)
            for (uint32_t p : s.passes)
                if (p < plan.passQueues_.size()) plan.passQueues_[p] = s.queue;
    }
};

}  // namespace skygraph::detail
