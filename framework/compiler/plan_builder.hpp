// The compiler's write access to a Plan (include/skygraph/plan.hpp), which is read-only to
// everyone else: compile() (the synchronizer, then compiler.cpp) and planSetup /
// planImageRead (transfer_plans.cpp) fill a plan through these functions and nothing else.
//
// Storage: a Plan keeps all usages of all passes in one array and all pass barriers in
// another; each PlannedPass views its part of them through spans, and names (of passes, pass
// types, resources and slots) are views into string tables that copies of a plan share (they
// are never modified): the text of every name in the graph, culled passes' and unused
// resources' included, and the compiler's own (slots, inserted clears). So compiling makes a
// handful of allocations instead of one or more per pass and name. The spans point into the
// Plan that holds the pass: copying a Plan rebases them by their offset into those arrays
// (plan.cpp), so code that writes a plan keeps every non-empty span viewing that plan's own
// usages() and barriers(), and reserves those arrays before it points spans into them (they
// must not move afterwards). Moving a Plan keeps them valid.
#pragma once

#include <skygraph/plan.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace skygraph::detail {

// A plan holds one PlannedUsage per usage, and the compiler writes and reads them all: its
// members are ordered to pack into one 64-byte cache line.
static_assert(sizeof(PlannedUsage) == 64, "PlannedUsage: keep it one cache line");

struct PlanBuilder {
    static std::string& graph(Plan& p) noexcept { return p.graph_; }
    static FeatureValues& features(Plan& p) noexcept { return p.features_; }
    static void setOutputExtent(Plan& p, uint32_t width, uint32_t height) noexcept {
        p.outputWidth_ = width;
        p.outputHeight_ = height;
    }
    static LayoutPolicy& layouts(Plan& p) noexcept { return p.layouts_; }
    static std::vector<PlannedResource>& resources(Plan& p) noexcept { return p.resources_; }
    /// Each pass's spans view usages(p) and barriers(p) of the same plan.
    static std::vector<PlannedPass>& passes(Plan& p) noexcept { return p.passes_; }
    static std::vector<Barrier>& finalBarriers(Plan& p) noexcept { return p.finalBarriers_; }
    static std::vector<InPassBarrier>& inPassBarriers(Plan& p) noexcept { return p.inPassBarriers_; }
    static std::vector<CulledPass>& culled(Plan& p) noexcept { return p.culled_; }
    static std::vector<Presentation>& presentations(Plan& p) noexcept { return p.presentations_; }
    static MemoryLayout& memory(Plan& p) noexcept { return p.memory_; }
    static std::vector<Submit>& submits(Plan& p) noexcept { return p.submits_; }
    static std::vector<QueueKind>& passQueues(Plan& p) noexcept { return p.passQueues_; }
    static std::array<uint32_t, kQueueKinds>& queueFamilies(Plan& p) noexcept { return p.queueFamilies_; }
    static std::vector<uint8_t>& concurrent(Plan& p) noexcept { return p.concurrent_; }
    /// What Submit's spans view: call pointSubmits once they are complete.
    static std::vector<uint32_t>& submitPasses(Plan& p) noexcept { return p.submitPasses_; }
    static std::vector<SemaphoreOp>& semaphoreOps(Plan& p) noexcept { return p.semaphoreOps_; }
    static std::vector<Barrier>& releases(Plan& p) noexcept { return p.releases_; }
    /// A submit as vectors, before the plan's arrays hold it.
    struct SubmitDraft {
        QueueKind queue = QueueKind::Graphics;
        std::vector<uint32_t> passes;
        std::vector<SemaphoreOp> waits;
        std::vector<Barrier> releases;
        std::vector<SemaphoreOp> signals;
        bool waitsForAcquire = false;
    };
    /// Replaces the plan's submits with `drafts`, laid out in its arrays (reserved first, so
    /// that the spans stay put).
    static void setSubmits(Plan& p, const std::vector<SubmitDraft>& drafts) {
        p.submits_.clear();
        p.submitPasses_.clear();
        p.semaphoreOps_.clear();
        p.releases_.clear();
        size_t passes = 0, ops = 0, releases = 0;
        for (const SubmitDraft& d : drafts) {
            passes += d.passes.size();
            ops += d.waits.size() + d.signals.size();
            releases += d.releases.size();
        }
        p.submitPasses_.reserve(passes);
        p.semaphoreOps_.reserve(ops);
        p.releases_.reserve(releases);
        auto place = [](auto& into, const auto& from) {
            using T = typename std::remove_reference_t<decltype(into)>::value_type;
            const size_t at = into.size();
            into.insert(into.end(), from.begin(), from.end());
            return from.empty() ? std::span<const T>{} : std::span<const T>(into.data() + at, from.size());
        };
        for (const SubmitDraft& d : drafts) {
            Submit s;
            s.queue = d.queue;
            s.waitsForAcquire = d.waitsForAcquire;
            s.passes = place(p.submitPasses_, d.passes);
            s.waits = place(p.semaphoreOps_, d.waits);
            s.releases = place(p.releases_, d.releases);
            s.signals = place(p.semaphoreOps_, d.signals);
            p.submits_.push_back(s);
        }
    }
    /// Every pass in one graphics submit, without semaphores: a plan on one queue (whose
    /// passes need no queue of their own: Plan::queueOf says graphics).
    static void singleSubmit(Plan& p) {
        p.passQueues_.clear();
        p.submitPasses_.resize(p.passes_.size());
        for (size_t i = 0; i < p.passes_.size(); ++i) p.submitPasses_[i] = static_cast<uint32_t>(i);
        p.submits_.assign(1, Submit{});
        p.submits_[0].passes = p.submitPasses_;
        p.submits_[0].waitsForAcquire = !p.presentations_.empty();
    }

    /// Every pass's usages, pass after pass: what PlannedPass::usages views.
    static std::vector<PlannedUsage>& usages(Plan& p) noexcept { return p.usages_; }
    /// Every pass's barrier batch, pass after pass: what PlannedPass::barriers views.
    static std::vector<Barrier>& barriers(Plan& p) noexcept { return p.barriers_; }
    /// Keeps `names` alive as long as the plan (and its copies): the plan's names view it.
    static void keepNames(Plan& p, std::shared_ptr<const std::string> names) {
        p.nameTables_.push_back(std::move(names));
    }
    /// Lets `to` view the names that `from` views.
    static void shareNames(Plan& to, const Plan& from) {
        to.nameTables_.insert(to.nameTables_.end(), from.nameTables_.begin(), from.nameTables_.end());
    }
};

}  // namespace skygraph::detail
