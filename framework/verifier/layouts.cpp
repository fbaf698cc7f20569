// Layouts and contents, walked in recording order (Vulkan 1.3 §7.6.2 "Image Layout
// Transitions", §12.4 "Image Layouts", the render pass load and store operations, and the
// Memory Aliasing section's "writes via one alias make the contents ... undefined").
#include "checks.hpp"
#include "frame_resources.hpp"

#include <skygraph/format.hpp>

#include <algorithm>
#include <initializer_list>
#include <string>
#include <vector>

namespace skygraph::verifier {
namespace {

bool oneOf(VkImageLayout l, std::initializer_list<VkImageLayout> allowed) {
    return std::find(allowed.begin(), allowed.end(), l) != allowed.end();
}

/// Whether `l` names aspects the format has (§12.4): the DEPTH_ ones a depth aspect; the
/// STENCIL_ ones a stencil aspect and no depth, as a usage of a combined image covers both.
bool layoutFitsAspects(VkImageLayout l, const FormatInfo& f) {
    if (oneOf(l, {VK_IMAGE_LAYOUT_STENCIL_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_STENCIL_READ_ONLY_OPTIMAL}))
        return f.hasStencil && !f.hasDepth;
    if (oneOf(l, {VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL,
                  VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                  VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_STENCIL_READ_ONLY_OPTIMAL,
                  VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL}))
        return f.isDepthStencil() && (f.hasDepth || oneOf(l, {VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                                                              VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL}));
    return true;
}

/// The layouts a usage (or one half of a ReadWrite transfer) may be performed in.
bool layoutAllowed(const PlannedUsage& u, const FormatInfo& format, bool copyOut, bool copyIn, VkImageLayout l) {
    if (!layoutFitsAspects(l, format)) return false;
    const UsageMode& m = u.usage;
    switch (m.stage) {
        case skygraph::Stage::ColorAttachment:
            return oneOf(l, {VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_ATTACHMENT_OPTIMAL,
                             VK_IMAGE_LAYOUT_GENERAL});
        case skygraph::Stage::DepthAttachment: {
            const bool writable =
                oneOf(l, {VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                          VK_IMAGE_LAYOUT_STENCIL_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_ATTACHMENT_OPTIMAL,
                          VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_STENCIL_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL});
            if (writable) return true;
            // A depth attachment that is only read (no load-op clear) may use a read-only layout.
            const bool writes = accessTypes(u.access).has(AccessType::DepthStencilAttachmentWrite);
            return !writes && oneOf(l, {VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                                        VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_READ_ONLY_OPTIMAL,
                                        VK_IMAGE_LAYOUT_STENCIL_READ_ONLY_OPTIMAL,
                                        VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL});
        }
        case skygraph::Stage::Vertex:
        case skygraph::Stage::Fragment:
        case skygraph::Stage::Compute:
            if (resolvedBinding(m, true) == BindAs::Sampled)
                return oneOf(l, {VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_READ_ONLY_OPTIMAL,
                                 VK_IMAGE_LAYOUT_GENERAL}) ||
                       (format.isDepthStencil() &&
                        oneOf(l, {VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                                  VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_STENCIL_READ_ONLY_OPTIMAL,
                                  VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL}));
            return l == VK_IMAGE_LAYOUT_GENERAL;  // storage images
        case skygraph::Stage::Transfer: {
            const bool reads = copyOut || (!copyIn && m.access == Access::Read);
            return oneOf(l, {reads ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             VK_IMAGE_LAYOUT_GENERAL});
        }
        default: return false;  // vertex input and indirect reads are of buffers
    }
}

constexpr uint8_t kNoQueue = 0xff;

struct CellState {
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    /// Exclusive resources used by several queue families: the queue kind whose family owns
    /// it (kNoQueue: no family yet, its contents undefined), and a release's destination until
    /// the acquire.
    uint8_t owner = kNoQueue;
    uint8_t releasedTo = kNoQueue;
    /// The release the acquire must match (§7.7.4: the same layouts and range), while released.
    const TimelineItem* release = nullptr;
    bool defined = false;
    /// Another resource wrote the memory: this subresource must move from UNDEFINED before use.
    bool takenOver = false;
    std::string undefinedBecause = "it is never written in the frame";
};

class LayoutWalk {
public:
    LayoutWalk(const FrameModel& model, const Plan& plan, const GraphDesc& graph, Reporter& reporter)
        : model_(model), plan_(plan), graph_(graph), reporter_(reporter) {
        cells_.resize(model.memory.size());
        used_.assign(model.memory.size(), false);
        for (uint32_t o = 0; o < model.memory.size(); ++o) {
            const MemoryObject& obj = model.memory.object(o);
            CellState initial;
            if (obj.resource >= 0) {
                const PlannedResource& r = plan.resources()[static_cast<size_t>(obj.resource)];
                // A transient starts each frame undefined in heaps the frames share too: what
                // the previous frame left there is not its contents.
                const bool transient =
                    r.copies == ResourceCopies::PerFrameTransient || r.copies == ResourceCopies::SharedTransient;
                // Resources from outside the frame arrive in their initial layout, contents visible.
                initial.layout = transient ? VK_IMAGE_LAYOUT_UNDEFINED : r.initialLayout;
                initial.defined = !transient;
                if (!transient) initial.owner = static_cast<uint8_t>(QueueKind::Graphics);
            }
            cells_[o].assign(obj.cellCount(), initial);
        }
        // Which resources one family owns at a time: exclusive ones used by several families,
        // the graphics family among them for a resource from outside the frame or exported
        // (it owns those between frames).
        std::vector<uint8_t> familiesOf(plan.resources().size(), 0);
        for (size_t r = 0; r < plan.resources().size(); ++r)
            if (const uint32_t decl = plan.resources()[r].decl; decl < graph.resources.size())
                if (graph.resources[decl].external || graph.resources[decl].isExported())
                    familiesOf[r] = uint8_t(1u << static_cast<size_t>(QueueKind::Graphics));
        for (size_t i = 0; i < plan.passes().size(); ++i)
            for (const PlannedUsage& u : plan.passes()[i].usages)
                if (u.resource < familiesOf.size())
                    familiesOf[u.resource] |= uint8_t(1u << static_cast<size_t>(plan.queueOf(static_cast<uint32_t>(i))));
        owned_.assign(model.memory.size(), false);
        for (uint32_t o = 0; o < model.memory.size(); ++o) {
            const int32_t r = model.memory.object(o).resource;
            if (r < 0 || plan.concurrent(static_cast<uint32_t>(r))) continue;
            bool several = false;
            for (size_t a = 0; a < kQueueKinds; ++a)
                for (size_t b = 0; b < kQueueKinds; ++b)
                    several |= (familiesOf[size_t(r)] >> a & 1u) && (familiesOf[size_t(r)] >> b & 1u) &&
                               plan.queueFamilies()[a] != plan.queueFamilies()[b];
            owned_[o] = several;
        }
    }

    void run() {
        for (const TimelineItem& t : model_.timeline) {
            switch (t.kind) {
                case TimelineItem::Kind::Barrier: barrier(t); break;
                case TimelineItem::Kind::Usage: usage(t); break;
                case TimelineItem::Kind::FrameEnd: frameEnd(t); break;
                case TimelineItem::Kind::Present: present(t); break;
            }
        }
    }

private:
    /// Findings of the second frame that its per-frame copies would repeat are left out.
    bool reports(const TimelineItem& t) const { return t.frame == 1 || model_.memory.object(t.object).shared; }

    void add(FindingKind kind, const TimelineItem& t, std::string reason) {
        if (!reports(t)) return;
        Finding f;
        f.kind = kind;
        const MemoryObject& o = model_.memory.object(t.object);
        if (o.resource >= 0) f.resources.push_back(static_cast<uint32_t>(o.resource));
        f.resourceNames.push_back(o.name);
        f.earlier = t.site;
        f.reason = std::move(reason);
        reporter_.add(std::move(f));
    }

    template <class F>
    void forCells(uint32_t object, const SubresourceRange& r, F&& f) {
        const MemoryObject& o = model_.memory.object(object);
        if (o.kind != MemoryObject::Kind::Image) {
            f(cells_[object][0], 0u, 0u);
            return;
        }
        for (uint32_t mip = r.baseMip; mip < r.baseMip + r.mipCount; ++mip)
            for (uint32_t layer = r.baseLayer; layer < r.baseLayer + r.layerCount; ++layer)
                f(cells_[object][o.cell(mip, layer)], mip, layer);
    }

    /// A write through `object` leaves what other resources kept in the memory it shares
    /// with them undefined, and those must start again from UNDEFINED.
    void wroteMemory(uint32_t object, const FindingSite& site) {
        for (uint32_t other = 0; other < model_.memory.size(); ++other) {
            if (other == object || !model_.memory.placementsOverlap(object, other)) continue;
            for (CellState& c : cells_[other]) {
                c.defined = false;
                c.takenOver = true;
                c.undefinedBecause =
                    model_.memory.object(object).name + " wrote the memory they share at " + where(site);
            }
        }
    }

    static std::string where(const FindingSite& s) {
        return (s.step >= 0 ? "[" + std::to_string(s.step) + "] " : "") + s.pass;
    }

    bool sameFamily(uint8_t a, QueueKind b) const {
        return a != kNoQueue && plan_.queueFamilies()[a] == plan_.queueFamilies()[static_cast<size_t>(b)];
    }

    /// The ownership half of a barrier: a release marks the cells for their acquire, which
    /// takes them over; a transition from UNDEFINED takes them over with their contents gone.
    /// Returns false for a release, whose layout transition happens in its acquire.
    bool ownership(const TimelineItem& t, const Barrier& b) {
        if (!owned_[t.object]) return !t.release;
        std::string problem;
        bool badOld = false;
        std::string current;
        const TimelineItem* unmatched = nullptr;
        const bool image = model_.memory.object(t.object).kind == MemoryObject::Kind::Image;
        forCells(t.object, b.range, [&](CellState& c, uint32_t, uint32_t) {
            if (t.release) {
                if (c.owner != kNoQueue && !sameFamily(c.owner, t.queue) && problem.empty())
                    problem = "released by the " + std::string(toString(t.queue)) + " queue but owned by the " +
                              std::string(toString(static_cast<QueueKind>(c.owner))) + " queue's family";
                // The release performs the transition its acquire names (once, between the two),
                // so it leaves the current layout as its acquire would.
                if (image && b.oldLayout != VK_IMAGE_LAYOUT_UNDEFINED && b.oldLayout != c.layout && !badOld) {
                    badOld = true;
                    current = layoutNameShort(c.layout);
                }
                c.releasedTo = static_cast<uint8_t>(b.dstQueue);
                c.release = &t;
                return;
            }
            if (b.transfersOwnership()) {
                if (c.releasedTo == kNoQueue || !sameFamily(c.releasedTo, t.queue)) {
                    if (problem.empty())
                        problem = "acquired by the " + std::string(toString(t.queue)) +
                                  " queue with no release from the " + std::string(toString(b.srcQueue)) +
                                  " queue before it";
                } else if (c.release && !unmatched && !halvesAgree(*c.release->barrier, b, image)) {
                    unmatched = c.release;
                }
                c.owner = static_cast<uint8_t>(t.queue);
                c.releasedTo = kNoQueue;
                c.release = nullptr;
                return;
            }
            if (b.oldLayout == VK_IMAGE_LAYOUT_UNDEFINED && b.oldLayout != b.newLayout) {
                c.owner = static_cast<uint8_t>(t.queue);
                c.releasedTo = kNoQueue;
                c.release = nullptr;
            }
        });
        if (!problem.empty()) add(FindingKind::Ownership, t, problem);
        if (badOld)
            add(FindingKind::BadOldLayout, t,
                "the release's oldLayout " + layoutNameShort(b.oldLayout) + " is neither UNDEFINED nor the current " +
                    "layout " + current);
        if (unmatched) disagreeingHalves(*unmatched, t, image);
        return !t.release;
    }

    /// The release and the acquire of one ownership transfer must name the same queues and, for
    /// an image, the same layouts and subresource range (§7.7.4): the transition happens once,
    /// and an image whose halves disagree is left in a layout neither of them says.
    static bool halvesAgree(const Barrier& release, const Barrier& acquire, bool image) {
        if (release.srcQueue != acquire.srcQueue || release.dstQueue != acquire.dstQueue) return false;
        return !image || (release.oldLayout == acquire.oldLayout && release.newLayout == acquire.newLayout &&
                          release.range == acquire.range);
    }

    static std::string halfText(const Barrier& b, bool image) {
        std::string text = std::string(toString(b.srcQueue)) + " -> " + std::string(toString(b.dstQueue));
        if (image)
            text += ", " + layoutNameShort(b.oldLayout) + " -> " + layoutNameShort(b.newLayout) + " " +
                    rangeText(b.range);
        return text;
    }

    void disagreeingHalves(const TimelineItem& release, const TimelineItem& acquire, bool image) {
        if (!reports(acquire)) return;
        Finding f;
        f.kind = FindingKind::Ownership;
        const MemoryObject& o = model_.memory.object(acquire.object);
        if (o.resource >= 0) f.resources.push_back(static_cast<uint32_t>(o.resource));
        f.resourceNames.push_back(o.name);
        f.earlier = release.site;
        f.later = acquire.site;
        f.reason = "the release (" + halfText(*release.barrier, image) + ") and its acquire (" +
                   halfText(*acquire.barrier, image) + ") of one ownership transfer disagree";
        reporter_.add(std::move(f));
    }

    void barrier(const TimelineItem& t) {
        const Barrier& b = *t.barrier;
        if (!ownership(t, b)) return;
        bool badOld = false, notFromUndefined = false;
        std::string current;
        forCells(t.object, b.range, [&](CellState& c, uint32_t, uint32_t) {
            if (b.oldLayout != VK_IMAGE_LAYOUT_UNDEFINED && b.oldLayout != c.layout && !badOld) {
                badOld = true;
                current = layoutNameShort(c.layout);
            }
            if (c.takenOver && b.oldLayout != VK_IMAGE_LAYOUT_UNDEFINED) notFromUndefined = true;
            if (b.oldLayout == b.newLayout) return;
            c.layout = b.newLayout;
            if (b.oldLayout == VK_IMAGE_LAYOUT_UNDEFINED) {
                c.defined = false;
                c.takenOver = false;
                c.undefinedBecause = "the transition from UNDEFINED at " + where(t.site) + " discarded them";
            }
        });
        if (badOld)
            add(FindingKind::BadOldLayout, t,
                "oldLayout " + layoutNameShort(b.oldLayout) + " is neither UNDEFINED nor the current layout " +
                    current);
        if (notFromUndefined)
            add(FindingKind::AliasNotInitialized, t,
                "another resource wrote this memory since; its subresources must move from UNDEFINED, not " +
                    layoutNameShort(b.oldLayout));
        if (b.oldLayout != b.newLayout) wroteMemory(t.object, t.site);
    }

    /// A use on a queue whose family does not own the contents it keeps.
    void checkOwner(const TimelineItem& t, const SubresourceRange& range) {
        if (!owned_[t.object]) return;
        std::string problem;
        forCells(t.object, range, [&](CellState& c, uint32_t, uint32_t) {
            // Between the halves no queue owns it: "access after a release operation has
            // undefined results" (§7.7.4), on the releasing family as much as any other.
            if (c.releasedTo != kNoQueue && problem.empty())
                problem = "used on the " + std::string(toString(t.queue)) + " queue after its release to the " +
                          std::string(toString(static_cast<QueueKind>(c.releasedTo))) +
                          " queue's family and before the acquire";
            if (c.owner != kNoQueue && !sameFamily(c.owner, t.queue) && c.defined && problem.empty())
                problem = "used on the " + std::string(toString(t.queue)) + " queue while the " +
                          std::string(toString(static_cast<QueueKind>(c.owner))) +
                          " queue's family owns it: no ownership transfer";
            c.owner = static_cast<uint8_t>(t.queue);
        });
        if (!problem.empty()) add(FindingKind::Ownership, t, problem);
    }

    void usage(const TimelineItem& t) {
        const PlannedUsage& u = *t.usage;
        const MemoryObject& o = model_.memory.object(t.object);
        const bool image = o.kind == MemoryObject::Kind::Image;
        checkOwner(t, image ? u.range : o.whole());
        if (image) checkLayout(t, u);
        // Taking over memory: every subresource moves from UNDEFINED before the first use.
        const bool first = !used_[t.object];
        used_[t.object] = true;
        const SubresourceRange range = image ? u.range : o.whole();
        size_t notMoved = 0;
        if (image)
            forCells(t.object, first ? o.whole() : range,
                     [&](CellState& c, uint32_t, uint32_t) { notMoved += c.takenOver; });
        if (notMoved)
            add(FindingKind::AliasNotInitialized, t,
                std::to_string(notMoved) +
                    " subresource(s) of memory another resource wrote were not moved from "
                    "UNDEFINED before this use");
        const bool attachment = isAttachmentStage(u.usage.stage);
        const bool reads = t.copyOut || (!t.copyIn && readsContents(u.usage.access));
        const bool writes = t.copyIn || (!t.copyOut && writesContents(u.usage.access));
        if (attachment && u.load != LoadOp::Load)
            forCells(t.object, range, [&](CellState& c, uint32_t, uint32_t) {
                c.defined = u.load == LoadOp::Clear;
                if (!c.defined) c.undefinedBecause = "its DONT_CARE load op discarded them";
            });
        if (reads) {
            std::string why;
            forCells(t.object, range, [&](CellState& c, uint32_t, uint32_t) {
                if (!c.defined && why.empty()) why = c.undefinedBecause;
            });
            if (!why.empty()) add(FindingKind::UndefinedContents, t, "reads contents that are undefined: " + why);
        }
        if (writes || (attachment && u.load == LoadOp::Clear)) {
            forCells(t.object, range, [&](CellState& c, uint32_t, uint32_t) { c.defined = true; });
            wroteMemory(t.object, t.site);
        }
        // STORE_OP_NONE keeps the contents only where the render pass wrote nothing (the load
        // op's clear included); after a write it behaves as DONT_CARE (VkAttachmentStoreOp).
        const bool discards = u.store == StoreOp::DontCare ||
                              (u.store == StoreOp::None && (writes || u.load == LoadOp::Clear));
        if (attachment && discards)
            forCells(t.object, range, [&](CellState& c, uint32_t, uint32_t) {
                c.defined = false;
                c.undefinedBecause = std::string(u.store == StoreOp::None ? "the NONE store op after a write"
                                                                          : "the DONT_CARE store op") +
                                     " at " + where(t.site) + " discarded them";
            });
    }

    void checkLayout(const TimelineItem& t, const PlannedUsage& u) {
        const MemoryObject& o = model_.memory.object(t.object);
        const ResourceDesc& d = graph_.resources[plan_.resources()[static_cast<size_t>(o.resource)].decl];
        if (!layoutAllowed(u, d.format, t.copyOut, t.copyIn, u.layout))
            add(FindingKind::LayoutNotAllowed, t,
                "a " + toString(u.usage) + " usage cannot be in " + layoutNameShort(u.layout));
        std::string mismatch;
        forCells(t.object, u.range, [&](CellState& c, uint32_t mip, uint32_t layer) {
            if (c.layout != u.layout && mismatch.empty())
                mismatch = "mip " + std::to_string(mip) + " layer " + std::to_string(layer) + " is in " +
                           layoutNameShort(c.layout);
        });
        if (!mismatch.empty())
            add(FindingKind::LayoutMismatch, t, "the usage expects " + layoutNameShort(u.layout) + " but " + mismatch);
    }

    void frameEnd(const TimelineItem& t) {
        const auto& objects = model_.objectOf.at(t.frame - 1);
        for (size_t r = 0; r < objects.size(); ++r) {
            if (objects[r] < 0) continue;
            const PlannedResource& pr = plan_.resources()[r];
            const auto object = static_cast<uint32_t>(objects[r]);
            const MemoryObject& o = model_.memory.object(object);
            TimelineItem at = t;
            at.object = object;
            if (owned_[object]) handedBack(at, graph_.resources[pr.decl]);
            if (o.readAfterFrame) handedOutDefined(at);
            if (o.kind != MemoryObject::Kind::Image || !o.handedOut) continue;
            std::string wrong;
            for (const CellState& c : cells_[object])
                if (c.layout != pr.finalLayout && wrong.empty()) wrong = layoutNameShort(c.layout);
            if (!wrong.empty())
                add(FindingKind::FinalLayout, at,
                    "the frame leaves it in " + wrong + ", the plan says " + layoutNameShort(pr.finalLayout));
            if (!perFrameInFlight(pr.copies) && pr.finalLayout != pr.initialLayout && t.frame == 1)
                add(FindingKind::FinalLayout, at,
                    "shared across frames, it ends in " + layoutNameShort(pr.finalLayout) +
                        " but the next frame expects " + layoutNameShort(pr.initialLayout));
        }
    }

    /// An export is read after the frame in its final state: a final barrier from UNDEFINED, or
    /// a DONT_CARE store, would hand that reader contents that are not there.
    void handedOutDefined(const TimelineItem& t) {
        std::string why;
        for (const CellState& c : cells_[t.object])
            if (!c.defined && why.empty()) why = c.undefinedBecause;
        if (!why.empty())
            add(FindingKind::UndefinedContents, t,
                "exported, it is read after the frame, but the frame leaves its contents undefined: " + why);
    }

    /// What outlives the frame (external or exported) is the graphics family's between frames:
    /// the frame gives back what another family took, released and acquired.
    void handedBack(const TimelineItem& t, const ResourceDesc& d) {
        if (!d.external && !d.isExported()) return;
        std::string problem;
        for (const CellState& c : cells_[t.object]) {
            if (!problem.empty()) break;
            if (c.releasedTo != kNoQueue)
                problem = "released to the " + std::string(toString(static_cast<QueueKind>(c.releasedTo))) +
                          " queue's family and never acquired";
            else if (c.defined && c.owner != kNoQueue && !sameFamily(c.owner, QueueKind::Graphics))
                problem = "the frame leaves it owned by the " + std::string(toString(static_cast<QueueKind>(c.owner))) +
                          " queue's family; the graphics family owns it between frames";
        }
        if (!problem.empty()) add(FindingKind::Ownership, t, problem);
    }

    void present(const TimelineItem& t) {
        std::string wrong;
        bool undefined = false;
        for (const CellState& c : cells_[t.object]) {
            if (c.layout != VK_IMAGE_LAYOUT_PRESENT_SRC_KHR && wrong.empty()) wrong = layoutNameShort(c.layout);
            undefined |= !c.defined;
        }
        if (!wrong.empty()) add(FindingKind::PresentLayout, t, "presented in " + wrong + ", not PRESENT_SRC_KHR");
        if (undefined) add(FindingKind::UndefinedContents, t, "presents contents that are undefined");
    }

    const FrameModel& model_;
    const Plan& plan_;
    const GraphDesc& graph_;
    Reporter& reporter_;
    std::vector<std::vector<CellState>> cells_;  // per object, per subresource
    std::vector<bool> used_;                     // per object: a usage has been seen
    std::vector<bool> owned_;                    // per object: one family owns it at a time
};

}  // namespace

void checkLayoutsAndContents(const FrameModel& model, const Plan& plan, const GraphDesc& graph, Reporter& reporter) {
    LayoutWalk(model, plan, graph, reporter).run();
}

}  // namespace skygraph::verifier
