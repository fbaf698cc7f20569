// The plan verifier: an independent check that a compiled Plan is free of data races, layout
// errors and memory-aliasing errors under the Vulkan 1.3 memory model, from the plan alone,
// with no device. It is independent of the compiler: it derives every dependency from the
// plan itself instead of trusting how the plan was made, so it also catches plans a compiler
// bug produced, and checks plans edited by hand.
// docs/verifier.md says what it models and which checks are known to fail when they should.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph::verifier {

enum class FindingKind : uint8_t {
    MalformedPlan,        ///< An index out of range, an empty or oversized range, a bad barrier kind.
    InvalidMask,          ///< An access type no stage of the mask performs, or an unmodelled bit.
    UsageScope,           ///< A usage's stages or access miss what its usage (and load/store ops) does.
    /// No execution dependency chain between two conflicting accesses, or from an ownership
    /// transfer's release to its acquire.
    Unordered,
    NotAvailable,         ///< A write that no barrier makes available before the later access.
    NotVisible,           ///< A write made available but not visible to the later access.
    PartialAliasBarrier,  ///< A dependency between resources sharing memory through a barrier naming part of a
                          ///< resource.
    LayoutMismatch,       ///< A usage's layout is not the subresource's current layout.
    LayoutNotAllowed,     ///< A usage's layout is not one its usage may be performed in.
    BadOldLayout,         ///< A barrier's oldLayout is neither the current layout nor UNDEFINED.
    UndefinedContents,    ///< A read of contents that were never written or were discarded.
    AliasNotInitialized,  ///< A resource taking over memory has a subresource not moved from UNDEFINED.
    LiveOverlap,          ///< Two resources whose placements overlap are in use at the same time.
    PlacementInvalid,     ///< A placement outside its heap, misaligned, of a memory type its heap lacks, or of a
                          ///< resource that must not have one.
    PresentLayout,        ///< A presented image is not in PRESENT_SRC_KHR when presented.
    FinalLayout,          ///< A resource's layout after the frame differs from PlannedResource::finalLayout.
    /// An exclusive resource used on a queue of a family that does not own it, or between a
    /// release and its acquire, or an acquire with no release before it (or a release of what
    /// the family does not own), or a release whose queues, layouts or range differ from its
    /// acquire's.
    Ownership,
    /// A semaphore wait for a value that no signal of the frame reaches, or signal values of
    /// one semaphore that do not grow.
    Semaphore,
};
/// The enumerator's name, e.g. "NotVisible"; a view of static storage.
[[nodiscard]] std::string_view toString(FindingKind kind) noexcept;

/// One side of a finding: an access, a barrier or an agent outside the frame.
struct FindingSite {
    uint32_t frame = 1;  ///< 1, or 2 for the second frame of a shared resource.
    /// Index into Plan::passes(); -1 before the first step (the presentation engine), and
    /// passes().size() after the last (final barriers, the present, the host).
    int64_t step = -1;
    std::string pass;  ///< The step's name, or what stands there ("final barriers", "host").
    std::string what;  ///< e.g. "usage 1 Write@Compute as storage", "barrier 0 (UNDEFINED -> GENERAL)".
};

struct Finding {
    FindingKind kind = FindingKind::MalformedPlan;
    std::vector<uint32_t> resources;  ///< Indices into Plan::resources() (one, or two for aliases).
    std::vector<std::string> resourceNames;
    FindingSite earlier;  ///< The first access; for single-site findings the site itself.
    FindingSite later;    ///< The second access; empty `pass` for single-site findings.
    /// Two accesses to one image: the subresources both touch (zero counts otherwise).
    SubresourceRange subresources{0, 0, 0, 0};
    std::string reason;  ///< One line.
};

struct VerifyOptions {
    /// Also verify a second frame against the first for resources shared across frames.
    bool consecutiveFrames = true;
    /// Stop collecting after this many findings (VerificationReport::truncated says so).
    size_t maxFindings = 200;
};

struct VerificationReport {
    std::vector<Finding> findings;
    bool truncated = false;
    size_t accessesChecked = 0;  ///< Accesses (usages, transitions, outside agents) in the model.
    size_t pairsChecked = 0;     ///< Pairs of accesses to overlapping memory, one of them writing.

    [[nodiscard]] bool ok() const noexcept { return findings.empty(); }
    [[nodiscard]] size_t count(FindingKind kind) const noexcept;
    /// "ok: 41 accesses, 97 pairs" or one line per finding after a count.
    [[nodiscard]] std::string summary() const;
};

/// One finding on one line: "NotVisible hdr (frame 1): [2] tonemap usage 0 ... after [1] ...: reason".
[[nodiscard]] std::string format(const Finding& finding);

/// Verifies `plan`, compiled from `graph` (PlannedResource::decl indexes graph.resources, whose
/// shapes are resolved at plan.outputWidth() x plan.outputHeight()). Never throws for a bad
/// plan: indices out of range and the like are findings of kind MalformedPlan, and the items
/// they concern are left out of the rest of the checks.
[[nodiscard]] VerificationReport verifyPlan(const Plan& plan, const GraphDesc& graph,
                                            const VerifyOptions& options = {});

}  // namespace skygraph::verifier
