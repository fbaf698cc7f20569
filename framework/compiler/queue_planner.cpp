// Submits, semaphores and ownership transfers (docs/queues.md). One sweep over the plan's
// passes in order keeps, per subresource, who last wrote it and who read it since, on which
// queue, and which queue family owns it; a pass whose access meets an access of another queue
// waits for that queue, and an exclusive resource that must keep its contents moves to the
// pass's family through a release/acquire pair. queue_schedule.cpp cuts the schedule this
// decides into submits: before a pass that waits, after a pass that another queue waits for.
#include "queue_planner.hpp"

#include "plan_builder.hpp"
#include "queue_schedule.hpp"
#include "queue_scopes.hpp"
#include "vulkan_state.hpp"

#include <skygraph/diagnostics.hpp>

#include <algorithm>
#include <array>
#include <optional>
#include <set>

namespace skygraph {
namespace {

constexpr uint8_t kNoOwner = 0xff;
constexpr size_t kGraphics = static_cast<size_t>(QueueKind::Graphics);

size_t slot(QueueKind q) { return static_cast<size_t>(q); }
QueueKind kindAt(size_t i) { return static_cast<QueueKind>(i); }

/// One subresource through the frame.
struct Cell {
    int32_t lastWrite = kNever;  // pass index (a usage's write or a layout transition)
    uint8_t writeQueue = 0;
    VkPipelineStageFlags2 writeStages = 0;  // where that write happens
    VkAccessFlags2 writeAccess = 0;
    /// Per queue: the stages that barriers of that queue made the last write visible to.
    std::array<VkPipelineStageFlags2, kQueueKinds> visibleStages{};
    std::array<VkAccessFlags2, kQueueKinds> visibleAccess{};
    /// Before the frame's first write: the source scope of the first barrier (on any queue),
    /// which orders the cell's use after the previous frame's or the outside world's.
    VkPipelineStageFlags2 initialSrcStages = 0;
    VkAccessFlags2 initialSrcAccess = 0;
    std::array<int32_t, kQueueKinds> readSince{kNever, kNever, kNever};  // since lastWrite
    std::array<VkPipelineStageFlags2, kQueueKinds> readStagesSince{};
    std::array<int32_t, kQueueKinds> lastUse{kNever, kNever, kNever};
    std::array<VkPipelineStageFlags2, kQueueKinds> useStages{};  // of lastUse
    std::array<VkAccessFlags2, kQueueKinds> useAccess{};
    std::array<VkPipelineStageFlags2, kQueueKinds> frameStages{};  // of every use in the frame so far
    std::array<VkAccessFlags2, kQueueKinds> frameAccess{};
    bool touched = false;  // used in the frame so far, on any queue
    /// The last acquire of an ownership transfer since lastWrite, with no layout change (one with
    /// a change is a write): the pass, its queue and its destination stages.
    int32_t acquire = kNever;
    uint8_t acquireQueue = 0;
    VkPipelineStageFlags2 acquireStages = 0;
    uint8_t owner = kNoOwner;  // the queue kind whose family owns it; kNoOwner: nothing to keep
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

/// What one pass (or the frame's end) waits for, per queue: the last pass it needs there, the
/// stages it waits at, and the stages of the accesses it waits for (which the signal must hold).
struct Needs {
    std::array<int32_t, kQueueKinds> source{kNever, kNever, kNever};
    std::array<VkPipelineStageFlags2, kQueueKinds> stages{};
    std::array<VkPipelineStageFlags2, kQueueKinds> sourceStages{};
    void add(size_t queue, int32_t pass, VkPipelineStageFlags2 at, VkPipelineStageFlags2 from) {
        source[queue] = std::max(source[queue], pass);
        stages[queue] |= at;
        sourceStages[queue] |= from;
    }
};

class QueuePlanner {
public:
    QueuePlanner(const GraphIndex& index, const CompileOptions& options, Plan& plan)
        : graph_(index.graph()), index_(index), options_(options), plan_(plan) {}

    void run() {
        detail::PlanBuilder::queueFamilies(plan_) = options_.queueFamilies;
        assignQueues();
        if (std::all_of(schedule_.queues.begin(), schedule_.queues.end(), [](QueueKind q) { return q == QueueKind::Graphics; })) {
            detail::PlanBuilder::singleSubmit(plan_);
            return;
        }
        checkPresentedOnGraphics();
        chooseSharing();
        startCells();
        gatherLaterReadsOnTheQueue();
        const auto& passes = plan_.passes();
        schedule_.barriers.resize(passes.size());
        schedule_.waits.resize(passes.size());
        schedule_.signalStages.assign(passes.size(), 0);
        for (uint32_t i = 0; i < passes.size(); ++i) planPass(i);
        planFrameEnd();
        writeSubmits(std::move(schedule_), plan_);
    }

private:
    // ---- which queue, which sharing ----------------------------------------------------
    void assignQueues() {
        const auto& passes = plan_.passes();
        schedule_.queues.resize(passes.size(), QueueKind::Graphics);
        // Inserted steps run where the pass they serve runs, when that queue can record them:
        // a clear or clobber before its first user (image clears need graphics or compute,
        // depth clears graphics); read-backs at the end, on the graphics queue.
        for (size_t i = passes.size(); i-- > 0;) {
            const PlannedPass& p = passes[i];
            if (p.declIndex >= 0) {
                schedule_.queues[i] = graph_.passes[static_cast<size_t>(p.declIndex)].queue;
                continue;
            }
            if (p.type == "Readback" || i + 1 == passes.size()) continue;
            QueueKind next = schedule_.queues[i + 1];
            const PlannedResource& r = plan_.resources()[p.usages[0].resource];
            const ResourceDesc& d = graph_.resources[r.decl];
            if (d.isImage() && next == QueueKind::Transfer) next = QueueKind::Compute;
            if (d.isImage() && d.format.isDepthStencil()) next = QueueKind::Graphics;
            schedule_.queues[i] = next;
        }
    }

    /// A presented image is the graphics queue's (its acquire and present are there).
    void checkPresentedOnGraphics() const {
        const auto& passes = plan_.passes();
        for (const Presentation& pr : plan_.presentations())
            for (size_t i = 0; i < passes.size(); ++i)
                for (const PlannedUsage& u : passes[i].usages)
                    if (u.resource == pr.resource && schedule_.queues[i] != QueueKind::Graphics) {
                        const std::string name(plan_.resources()[pr.resource].name);
                        Diagnostics d;
                        d.add({graph_.file,
                               passes[i].declIndex >= 0 ? graph_.passes[size_t(passes[i].declIndex)].jsonPath + ".queue" : "",
                               std::string(passes[i].name), name,
                               "uses the presented image '" + name + "' on the " + std::string(toString(schedule_.queues[i])) +
                                   " queue; presented images are used on the graphics queue"});
                        throw GraphError(std::move(d));
                    }
    }

    uint32_t family(size_t queue) const { return options_.queueFamilies[queue]; }
    bool sameFamily(size_t a, size_t b) const { return family(a) == family(b); }

    /// Concurrent where the file says so; by default for buffers (they have no compression to
    /// lose) and for images that two families read one after the other with no write between
    /// (exclusive ownership would serialize those reads with a transfer); exclusive otherwise.
    /// Only resources used by more than one family need either.
    void chooseSharing() {
        const auto& resources = plan_.resources();
        std::vector<uint8_t> families(resources.size(), 0);  // bit per queue kind
        std::vector<uint8_t> readBy(resources.size(), 0);    // families reading since the last write
        std::vector<uint8_t> readsShared(resources.size(), 0);
        for (size_t i = 0; i < plan_.passes().size(); ++i)
            for (const PlannedUsage& u : plan_.passes()[i].usages) {
                const size_t q = slot(schedule_.queues[i]);
                families[u.resource] |= uint8_t(1u << q);
                if (writeBits(u.access) != 0) {
                    readBy[u.resource] = 0;
                    continue;
                }
                for (size_t x = 0; x < kQueueKinds; ++x)
                    if ((readBy[u.resource] >> x & 1u) && !sameFamily(x, q)) readsShared[u.resource] = 1;
                readBy[u.resource] |= uint8_t(1u << q);
            }
        auto& concurrent = detail::PlanBuilder::concurrent(plan_);
        concurrent.assign(resources.size(), 0);
        exclusive_.assign(resources.size(), 0);
        for (size_t r = 0; r < resources.size(); ++r) {
            const ResourceDesc& d = graph_.resources[resources[r].decl];
            // A resource that crosses renderers (external or exported) is created by one plan
            // and used by another: exclusive, owned by graphics between frames, is what
            // both keep without knowing each other's queues. So the graphics family is one of
            // its users even when no pass of this frame runs there.
            const bool crossesRenderers = d.external || d.isExported();
            const uint8_t users = families[r] | (crossesRenderers ? uint8_t(1u << kGraphics) : uint8_t(0));
            bool several = false;
            for (size_t a = 0; a < kQueueKinds; ++a)
                for (size_t b = 0; b < kQueueKinds; ++b)
                    several |= (users >> a & 1u) && (users >> b & 1u) && !sameFamily(a, b);
            const Sharing s = d.sharing != Sharing::Auto                           ? d.sharing
                              : crossesRenderers                                     ? Sharing::Exclusive
                              : !d.isImage() || readsShared[r]                       ? Sharing::Concurrent
                                                                                     : Sharing::Exclusive;
            concurrent[r] = several && s == Sharing::Concurrent;
            exclusive_[r] = several && s == Sharing::Exclusive;
        }
    }

    void startCells() {
        const auto& resources = plan_.resources();
        firstCell_.resize(resources.size() + 1);
        grids_.resize(resources.size());
        for (size_t r = 0; r < resources.size(); ++r) {
            grids_[r] = index_.grid(resources[r].decl);
            firstCell_[r + 1] = firstCell_[r] + static_cast<uint32_t>(grids_[r].size());
        }
        cells_.resize(firstCell_.back());
        lastUseOf_.assign(resources.size(), {kNever, kNever, kNever});
        useStagesOf_.assign(resources.size(), {});
        for (size_t r = 0; r < resources.size(); ++r) {
            const bool external = graph_.resources[resources[r].decl].external;
            for (uint32_t c = firstCell_[r]; c < firstCell_[r + 1]; ++c) {
                cells_[c].layout = resources[r].initialLayout;
                if (external) cells_[c].owner = static_cast<uint8_t>(kGraphics);
            }
        }
    }

    /// Per pass and plan resource, the stages and accesses with which later passes on the
    /// pass's queue read the subresources it uses before any of them is written again. A run of
    /// reads shares one barrier, so when the pass acquires the resource from another family,
    /// that acquire is all that orders those reads after the transfer: its destination scope
    /// holds theirs too (§7.7.4: accesses of the acquiring queue happen after the acquire only
    /// through its second scope).
    void gatherLaterReadsOnTheQueue() {
        const auto& passes = plan_.passes();
        struct Pending {
            std::array<VkPipelineStageFlags2, kQueueKinds> stages{};
            std::array<VkAccessFlags2, kQueueKinds> access{};
        };
        std::vector<Pending> pending(cells_.size());
        laterReads_.assign(passes.size(), {});
        // What the frame leaves carries on: on the graphics family, the next frame (which repeats
        // this one: its first reads, before any write) and the state it is left in are used next.
        const auto& resources = plan_.resources();
        for (size_t r = 0; r < resources.size(); ++r) {
            const ResourceDesc& d = graph_.resources[resources[r].decl];
            if (!d.external && !d.isExported()) continue;
            const ExternalState end = leftIn(d);
            const VulkanScope next = externalScope(d, end);
            for (uint32_t c = firstCell_[r]; c < firstCell_[r + 1]; ++c) {
                pending[c].stages[kGraphics] = next.stages ? next.stages : VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
                pending[c].access[kGraphics] = next.stages ? next.access : VK_ACCESS_2_MEMORY_READ_BIT;
            }
        }
        std::vector<uint8_t> written(cells_.size(), 0);
        for (size_t i = 0; i < passes.size(); ++i)
            for (const PlannedUsage& u : passes[i].usages)
                forCells(u.resource, u.range, [&](uint32_t c, const SubresourceRange&) {
                    if (written[c] || schedule_.queues[i] != QueueKind::Graphics) {
                        written[c] |= writeBits(u.access) != 0;
                        return;
                    }
                    if (writeBits(u.access)) written[c] = 1;
                    else if (pending[c].stages[kGraphics] != 0) {  // carried over
                        pending[c].stages[kGraphics] |= u.stages;
                        pending[c].access[kGraphics] |= u.access;
                    }
                });
        for (size_t i = passes.size(); i-- > 0;) {
            const size_t q = slot(schedule_.queues[i]);
            for (const PlannedUsage& u : passes[i].usages) {
                LaterReads later{u.resource, 0, 0};
                forCells(u.resource, u.range, [&](uint32_t c, const SubresourceRange&) {
                    later.stages |= pending[c].stages[q];
                    later.access |= pending[c].access[q];
                });
                if (later.stages) laterReads_[i].push_back(later);
            }
            for (const PlannedUsage& u : passes[i].usages)
                forCells(u.resource, u.range, [&](uint32_t c, const SubresourceRange&) {
                    if (writeBits(u.access)) pending[c] = {};
                    else {
                        pending[c].stages[q] |= u.stages;
                        pending[c].access[q] |= u.access;
                    }
                });
        }
    }

    /// The state the frame leaves an external or exported resource in, where its next user
    /// (the next frame, or the application) finds it.
    ExternalState leftIn(const ResourceDesc& d) const {
        const ExternalState end = d.isExported() ? d.final : d.initial;
        return end == ExternalState::Present ? options_.presentReplacement : end;
    }

    /// An acquire by pass i of resource r on its queue also waits for what laterReads_ holds.
    void waitForLaterReads(uint32_t i, Barrier& acquire) const {
        for (const LaterReads& later : laterReads_[i])
            if (later.resource == acquire.resource) {
                acquire.dstStages |= later.stages;
                acquire.dstAccess |= later.access;
            }
    }

    template <class F>
    void forCells(uint32_t r, const SubresourceRange& range, F&& f) {
        const SubresourceGrid& g = grids_[r];
        if (!graph_.resources[plan_.resources()[r].decl].isImage()) return f(firstCell_[r], SubresourceRange{0, 1, 0, 1});
        for (uint32_t m = range.baseMip; m < range.baseMip + range.mipCount; ++m)
            for (uint32_t l = range.baseLayer; l < range.baseLayer + range.layerCount; ++l)
                f(firstCell_[r] + static_cast<uint32_t>(g.index(m, l)), SubresourceRange{m, 1, l, 1});
    }

    bool isImage(uint32_t r) const { return graph_.resources[plan_.resources()[r].decl].isImage(); }

    /// The queue kind whose family must hand `c` over to queue `q` before it is used with its
    /// contents, or kNoOwner.
    uint8_t handsOver(uint32_t r, const Cell& c, size_t q, bool contentsKept) const {
        if (!exclusive_[r] || c.owner == kNoOwner || !contentsKept || sameFamily(c.owner, q)) return kNoOwner;
        return c.owner;
    }

    /// What every cell of `b`'s range hands over to queue q from (handsOver), when they all
    /// agree; nullopt when they differ.
    std::optional<uint8_t> commonHandOver(const Barrier& b, size_t q, bool kept) {
        std::optional<uint8_t> from;
        bool agree = true;
        forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) {
            const uint8_t o = handsOver(b.resource, cells_[c], q, kept);
            if (from && *from != o) agree = false;
            from = o;
        });
        return agree ? from : std::nullopt;
    }

    // ---- one pass --------------------------------------------------------------------
    void planPass(uint32_t i) {
        const PlannedPass& pass = plan_.passes()[i];
        const size_t q = slot(schedule_.queues[i]);
        Needs needs;
        if (q != kGraphics && !startedQueue_[q])
            needs.add(kGraphics, kFrameStart, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT);
        startedQueue_[q] = true;
        std::vector<Barrier>& batch = schedule_.barriers[i];
        for (const Barrier& b : pass.barriers) {
            if (b.kind == BarrierKind::Memory) {
                batch.push_back(b);
                continue;
            }
            const bool kept = isImage(b.resource) ? b.oldLayout != VK_IMAGE_LAYOUT_UNDEFINED : true;
            // One owner to take over from for the whole range, or none: the barrier stays one.
            if (const auto from = commonHandOver(b, q, kept)) {
                addBarrier(i, q, b, *from, needs);
                continue;
            }
            forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange& one) {
                Barrier piece = b;
                piece.range = one;
                addBarrier(i, q, piece, handsOver(b.resource, cells_[c], q, kept), needs);
            });
        }
        for (const PlannedUsage& u : pass.usages) needUsage(i, q, u, needs);
        for (const PlannedUsage& u : pass.usages) handOverForUse(i, q, u, needs);
        // The pass's own accesses, once everything it waits for is known.
        for (const Barrier& b : batch) {
            if (b.kind == BarrierKind::Memory) continue;
            const VkPipelineStageFlags2 dst = b.dstStages & queueStages(schedule_.queues[i]);
            const bool transition = b.oldLayout != b.newLayout && isImage(b.resource);
            const bool acquires = b.transfersOwnership();
            forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) {
                if (transition) write(cells_[c], i, q, dst, 0);
                else if (acquires) {
                    cells_[c].acquire = static_cast<int32_t>(i);
                    cells_[c].acquireQueue = static_cast<uint8_t>(q);
                    cells_[c].acquireStages = dst;
                }
                cells_[c].visibleStages[q] |= dst;
                cells_[c].visibleAccess[q] |= b.dstAccess & accessesOf(dst);
            });
        }
        for (const PlannedUsage& u : pass.usages) makeVisibleOnQueue(i, q, u);
        for (const PlannedUsage& u : pass.usages) recordUse(i, q, u);
        addWaits(i, q, needs);
        for (Barrier& b : batch) {
            keepToQueue(b, schedule_.queues[i]);
            readsIntoTransition(b);
        }
    }

    /// Barrier `b` of pass i (on queue q): what it waits for on other queues, and, when `from`
    /// is another family's queue, the acquire half of a transfer whose release goes there.
    void addBarrier(uint32_t i, size_t q, Barrier b, uint8_t from, Needs& needs) {
        const bool writes = b.oldLayout != b.newLayout || writeBits(b.dstAccess) != 0;
        forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) {
            if (cells_[c].lastWrite != kNever) return;
            cells_[c].initialSrcStages |= b.srcStages;
            cells_[c].initialSrcAccess |= b.srcAccess;
        });
        bool waits = false;
        forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) {
            waits |= needSources(cells_[c], q, writes, b.dstStages, needs);
        });
        if (b.aliasing) {
            const auto& placements = plan_.memory().placements;
            const uint32_t p = plan_.resources()[b.resource].placement;
            if (p != PlannedResource::kNoPlacement)
                for (uint32_t a : placements[p].aliases)
                    for (size_t x = 0; x < kQueueKinds; ++x)
                        if (x != q && lastUseOf_[a][x] != kNever) {
                            needs.add(x, lastUseOf_[a][x], b.dstStages, useStagesOf_[a][x]);
                            waits = true;
                        }
        }
        if (from != kNoOwner) {
            waitForLaterReads(i, b);
            Barrier release = releaseHalf(b, from, kindAt(q));
            int32_t source = kNever;
            forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) {
                const Cell& cell = cells_[c];
                if (cell.lastUse[from] > source) source = cell.lastUse[from];
                // A subresource that `from` only transitioned (the rest of a resource whose first
                // pass there uses part of it; its aliasing barrier covers all) is released after
                // that barrier, on that queue.
                if (cell.lastWrite != kNever && cell.writeQueue == from) {
                    if (cell.lastWrite > source) source = cell.lastWrite;
                    release.srcStages |= cell.writeStages;
                }
                cells_[c].owner = static_cast<uint8_t>(q);
            });
            if (source == kNever) {  // owned since the frame's start: released there
                source = kFrameStart;
                release.srcStages = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
            }
            if (source >= 0) releaseAfterFamily(source, from, b, release.srcStages);
            schedule_.releases.push_back({source, release});
            schedule_.signals[from].insert(source);
            if (source >= 0) schedule_.signalStages[static_cast<size_t>(source)] |= release.srcStages;
            needs.add(from, source, b.dstStages,
                      source == kFrameStart ? VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT : release.srcStages);
            b.srcQueue = release.srcQueue;
            b.dstQueue = release.dstQueue;
            waits = true;
        } else if (exclusive_[b.resource]) {
            forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) { cells_[c].owner = static_cast<uint8_t>(q); });
        }
        // Sources on other queues are the semaphore's: where every source is this frame's, the
        // barrier keeps only what its own queue did (on one VkQueue the other queue's stages would
        // order the accesses by themselves and hide a missing wait).
        bool thisFrame = waits && !b.aliasing;
        VkPipelineStageFlags2 ownStages = 0;
        VkAccessFlags2 ownAccess = 0;
        forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) {
            thisFrame &= cells_[c].touched;
            ownStages |= cells_[c].frameStages[q];
            ownAccess |= cells_[c].frameAccess[q];
        });
        if (thisFrame) {
            b.srcStages &= ownStages;
            b.srcAccess &= ownAccess & accessesOf(b.srcStages);
        }
        // The layout transition waits for the semaphore: the wait's stages chain into it. The
        // semaphore made the other queue's writes available; MEMORY_READ in the source access
        // scope changes nothing for Vulkan (reads need no availability), and is what validation
        // layer 1.3.239 needs to see the transition ordered after them (docs/queues.md).
        if (waits) {
            b.srcStages |= b.dstStages;
            b.srcAccess |= VK_ACCESS_2_MEMORY_READ_BIT;
        }
        if (isImage(b.resource))
            forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) { cells_[c].layout = b.newLayout; });
        schedule_.barriers[i].push_back(b);
    }

    /// The release half, on queue `from`, of the transfer whose acquire is `b`. The layout
    /// transition happens after the release (§7.7.4), so the release waits for what the
    /// barrier would have on one queue, where `from` has those stages (the last write and every
    /// read since, the outside world's included), and for `from`'s own uses since the last write.
    Barrier releaseHalf(const Barrier& b, uint8_t from, QueueKind to) {
        Barrier release = b;
        release.srcQueue = kindAt(from);
        release.dstQueue = to;
        release.dstStages = 0;
        release.dstAccess = 0;
        release.srcStages = b.srcStages & queueStages(kindAt(from));
        release.srcAccess = writeBits(b.srcAccess) & accessesOf(release.srcStages);
        forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) {
            const Cell& cell = cells_[c];
            if (cell.lastUse[from] == kNever) return;
            release.srcStages |= cell.useStages[from] | cell.readStagesSince[from];
            release.srcAccess |= writeBits(cell.useAccess[from]);
        });
        return release;
    }

    /// Ownership is the family's, but a release's first scope holds only its own queue's work,
    /// and the transition after it happens before the acquire, not after the semaphore waits of
    /// the acquiring side (§7.7.4). So the pass the release follows (`source`, on queue `from`)
    /// waits for the reads since the last write on the family's other queues; they come before
    /// it in the plan (the owner is the family's last user), so the wait closes no cycle.
    void releaseAfterFamily(int32_t source, size_t from, const Barrier& b, VkPipelineStageFlags2 releaseStages) {
        Needs extra;
        forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) {
            const Cell& cell = cells_[c];
            for (size_t x = 0; x < kQueueKinds; ++x)
                if (x != from && sameFamily(x, from) && cell.readSince[x] != kNever && cell.readSince[x] < source)
                    extra.add(x, cell.readSince[x], releaseStages, cell.readStagesSince[x]);
        });
        auto& waits = schedule_.waits[static_cast<size_t>(source)];
        for (size_t x = 0; x < kQueueKinds; ++x) {
            if (extra.source[x] == kNever) continue;
            const VkPipelineStageFlags2 stages = extra.stages[x] & queueStages(kindAt(from));
            // An earlier wait of the queue at those stages for that pass or a later one covers it;
            // the signal waited for then holds the reads' stages, as addWaits credits it.
            int32_t covering = kNever;
            for (int32_t p = source; p >= 0 && covering == kNever; --p)
                if (slot(schedule_.queues[static_cast<size_t>(p)]) == from)
                    for (const QueueWait& w : schedule_.waits[static_cast<size_t>(p)])
                        if (covering == kNever && w.queue == x && w.source >= extra.source[x] &&
                            ((w.stages & stages) == stages || (w.stages & VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT)))
                            covering = w.source;
            const int32_t signaller = covering != kNever ? covering : extra.source[x];
            schedule_.signalStages[static_cast<size_t>(signaller)] |= extra.sourceStages[x];
            if (covering != kNever) continue;
            schedule_.signals[x].insert(extra.source[x]);
            waits.push_back({x, extra.source[x], stages});
            waited_[from][x].emplace_back(extra.source[x], stages);
        }
    }

    /// Adds the other queues' accesses that an access of `c` on q must wait for: the last
    /// write, and when it writes, the reads since. Returns whether there were any.
    bool needSources(const Cell& c, size_t q, bool writes, VkPipelineStageFlags2 at, Needs& needs) {
        bool any = false;
        if (c.lastWrite != kNever && c.writeQueue != q) {
            needs.add(c.writeQueue, c.lastWrite, at, c.writeStages);
            any = true;
        }
        // The family took the cell over in that acquire: another queue of the family may use it
        // only after it (§7.7.4). Queues of other families take it over in acquires of their own,
        // whose releases follow it.
        if (c.acquire != kNever && c.acquireQueue != q && sameFamily(c.acquireQueue, q)) {
            needs.add(c.acquireQueue, c.acquire, at, c.acquireStages);
            any = true;
        }
        if (writes)
            for (size_t x = 0; x < kQueueKinds; ++x)
                if (x != q && c.readSince[x] != kNever) {
                    needs.add(x, c.readSince[x], at, c.readStagesSince[x]);
                    any = true;
                }
        return any;
    }

    void needUsage(uint32_t, size_t q, const PlannedUsage& u, Needs& needs) {
        const bool writes = writeBits(u.access) != 0;
        forCells(u.resource, u.range, [&](uint32_t c, const SubresourceRange&) { needSources(cells_[c], q, writes, u.stages, needs); });
    }

    /// A use of cells that another family owns and that no barrier of the pass took over (two
    /// reads in one layout): an acquire without a layout change, and its release.
    void handOverForUse(uint32_t i, size_t q, const PlannedUsage& u, Needs& needs) {
        if (!exclusive_[u.resource]) return;
        forCells(u.resource, u.range, [&](uint32_t c, const SubresourceRange& one) {
            const Cell& cell = cells_[c];
            const bool kept = isImage(u.resource) ? cell.layout != VK_IMAGE_LAYOUT_UNDEFINED : true;
            const uint8_t from = handsOver(u.resource, cell, q, kept);
            if (from == kNoOwner) return;
            Barrier b;
            b.resource = u.resource;
            b.kind = isImage(u.resource) ? BarrierKind::Image : BarrierKind::Buffer;
            b.range = isImage(u.resource) ? one : SubresourceRange{};
            b.oldLayout = b.newLayout = isImage(u.resource) ? cell.layout : VK_IMAGE_LAYOUT_UNDEFINED;
            b.dstStages = u.stages;
            b.dstAccess = u.access;
            addBarrier(i, q, b, from, needs);
        });
    }

    void write(Cell& c, int32_t pass, size_t q, VkPipelineStageFlags2 stages, VkAccessFlags2 access) {
        c.lastWrite = pass;
        c.writeQueue = static_cast<uint8_t>(q);
        c.writeStages = stages;
        c.writeAccess = access;
        c.readSince = {kNever, kNever, kNever};
        c.readStagesSince = {};
        c.visibleStages = {};
        c.visibleAccess = {};
        c.acquire = kNever;
    }

    /// A read run that spans queues has its barrier before its first reader, which may be on
    /// another queue: a reader on the writer's own queue whose stages no barrier of that queue
    /// made the write visible to gets a barrier of its own (without a layout change: the run
    /// shares one layout).
    void makeVisibleOnQueue(uint32_t i, size_t q, const PlannedUsage& u) {
        const auto pass = static_cast<int32_t>(i);
        forCells(u.resource, u.range, [&](uint32_t cell, const SubresourceRange& one) {
            Cell& c = cells_[cell];
            // Sources: a write of this queue, or, before any write of the frame, what the run's
            // first barrier (perhaps on another queue) waited for.
            const bool ownWrite = c.lastWrite != kNever && c.lastWrite != pass && c.writeQueue == q;
            const bool beforeFrameWrites = c.lastWrite == kNever && c.initialSrcStages != 0;
            if (!ownWrite && !beforeFrameWrites) return;
            if ((u.stages & ~c.visibleStages[q]) == 0 && (u.access & ~c.visibleAccess[q]) == 0) return;
            Barrier b;
            b.resource = u.resource;
            b.kind = isImage(u.resource) ? BarrierKind::Image : BarrierKind::Buffer;
            b.range = isImage(u.resource) ? one : SubresourceRange{};
            b.oldLayout = b.newLayout = isImage(u.resource) ? c.layout : VK_IMAGE_LAYOUT_UNDEFINED;
            b.srcStages = ownWrite ? c.writeStages : c.initialSrcStages;
            b.srcAccess = (ownWrite ? c.writeAccess : c.initialSrcAccess) & accessesOf(b.srcStages);
            b.dstStages = u.stages;
            b.dstAccess = u.access;
            c.visibleStages[q] |= u.stages;
            c.visibleAccess[q] |= u.access;
            schedule_.barriers[i].push_back(b);
        });
    }

    void recordUse(uint32_t i, size_t q, const PlannedUsage& u) {
        const bool writes = writeBits(u.access) != 0;
        const int32_t pass = static_cast<int32_t>(i);
        lastUseOf_[u.resource][q] = pass;
        useStagesOf_[u.resource][q] |= u.stages;
        forCells(u.resource, u.range, [&](uint32_t cell, const SubresourceRange&) {
            Cell& c = cells_[cell];
            if (writes) {
                write(c, pass, q, u.stages, writeBits(u.access));
            } else {
                c.readSince[q] = pass;
                c.readStagesSince[q] |= u.stages;
            }
            if (c.lastUse[q] != pass) c.useStages[q] = c.useAccess[q] = 0;
            c.lastUse[q] = pass;
            c.useStages[q] |= u.stages;
            c.useAccess[q] |= u.access;
            c.frameStages[q] |= u.stages;
            c.frameAccess[q] |= u.access;
            c.touched = true;
            if (exclusive_[u.resource]) c.owner = static_cast<uint8_t>(q);
        });
    }

    /// Keeps the needs that the queue's earlier waits do not already cover: a wait for a later
    /// pass of the same queue at no fewer stages.
    void addWaits(int32_t at, size_t q, const Needs& needs) {
        for (size_t x = 0; x < kQueueKinds; ++x) {
            if (x == q || needs.source[x] == kNever) continue;
            const int32_t source = needs.source[x];
            const VkPipelineStageFlags2 stages = needs.stages[x] & queueStages(kindAt(q));
            auto& history = waited_[q][x];
            const auto covering = std::find_if(history.begin(), history.end(), [&](const auto& w) {
                return w.first >= source && ((w.second & stages) == stages ||
                                             (w.second & VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT));
            });
            // The signal waited for holds the stages of every access it stands for.
            const int32_t signaller = covering != history.end() ? covering->first : source;
            if (signaller >= 0) schedule_.signalStages[static_cast<size_t>(signaller)] |= needs.sourceStages[x];
            if (covering != history.end()) continue;
            history.emplace_back(source, stages);
            if (at >= 0) schedule_.waits[static_cast<size_t>(at)].push_back({x, source, stages});
            else schedule_.endWaits.push_back({x, source, stages});
            schedule_.signals[x].insert(source);
        }
    }

    // ---- the frame's end ----------------------------------------------------------------
    /// The final barriers run in a last graphics submit that waits for every other queue's
    /// last pass (the frame ends on one queue, as it starts), after exclusive resources that
    /// outlive the frame came back to the graphics family.
    void planFrameEnd() {
        const size_t g = kGraphics;
        Needs needs;
        for (size_t i = 0; i < schedule_.queues.size(); ++i)
            if (slot(schedule_.queues[i]) != g)
                needs.add(slot(schedule_.queues[i]), static_cast<int32_t>(i), VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                          VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT);
        std::vector<Barrier> finals;
        const auto& resources = plan_.resources();
        std::vector<uint8_t> coveredByFinal(cells_.size(), 0);
        for (const Barrier& b : plan_.finalBarriers()) {
            if (b.kind == BarrierKind::Memory || !exclusive_[b.resource]) {
                finals.push_back(b);
                continue;
            }
            forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) { coveredByFinal[c] = 1; });
            if (const auto from = commonHandOver(b, g, true)) {
                finals.push_back(*from == kNoOwner ? b : acquireAtEnd(b, *from));
                continue;
            }
            forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange& one) {
                Barrier piece = b;
                piece.range = one;
                const uint8_t o = handsOver(b.resource, cells_[c], g, true);
                finals.push_back(o == kNoOwner ? piece : acquireAtEnd(piece, o));
            });
        }
        // Subresources no final barrier covers (already in their final layout) come back too.
        // Their acquire is all that orders the graphics queue's later work after the transfer,
        // so it waits in the scope the state they are left in is used in (the next frame's
        // uses, or the application's); a state without one, or General (whose next uses are
        // the frame's own, on any queue), gets every stage.
        for (size_t r = 0; r < resources.size(); ++r) {
            const ResourceDesc& d = graph_.resources[resources[r].decl];
            if (!exclusive_[r] || !(d.external || d.isExported())) continue;
            const ExternalState end = leftIn(d);
            VulkanScope next = externalScope(d, end);
            if (next.stages == 0 || end == ExternalState::General)
                next = {VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                        next.layout};
            const auto res = static_cast<uint32_t>(r);
            forCells(res, grids_[r].whole(), [&](uint32_t c, const SubresourceRange& one) {
                if (coveredByFinal[c]) return;
                const uint8_t from = handsOver(res, cells_[c], g, true);
                if (from == kNoOwner) return;
                Barrier b;
                b.resource = res;
                b.kind = isImage(res) ? BarrierKind::Image : BarrierKind::Buffer;
                b.range = isImage(res) ? one : SubresourceRange{};
                b.oldLayout = b.newLayout = cells_[c].layout;
                b.dstStages = next.stages;
                b.dstAccess = next.access;
                finals.push_back(acquireAtEnd(b, from));
            });
        }
        // The final barriers follow the join's wait: those of resources other queues used this
        // frame continue it, with MEMORY_READ as every barrier after a wait (validation layer
        // 1.3.239 needs it there too).
        for (Barrier& b : finals) {
            if (b.kind == BarrierKind::Memory) continue;
            bool otherQueues = false;
            forCells(b.resource, b.range, [&](uint32_t c, const SubresourceRange&) {
                for (size_t x = 0; x < kQueueKinds; ++x) otherQueues |= x != g && cells_[c].frameStages[x] != 0;
            });
            if (otherQueues) b.srcAccess |= VK_ACCESS_2_MEMORY_READ_BIT;
            readsIntoTransition(b);
        }
        detail::PlanBuilder::finalBarriers(plan_) = std::move(finals);
        addWaits(kNever, g, needs);
        // The frame's last pass on each other queue signals at every stage: the end waits
        // for all of its work, and the frame's fence with it.
        for (size_t x = 0; x < kQueueKinds; ++x)
            if (needs.source[x] >= 0) {
                schedule_.signals[x].insert(needs.source[x]);
                schedule_.signalStages[static_cast<size_t>(needs.source[x])] |= VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
            }
    }

    /// Final barrier `b` as the acquire half of a transfer back to the graphics family; the
    /// release goes after the last pass of the queue that owns it.
    Barrier acquireAtEnd(Barrier b, uint8_t from) {
        Barrier release = releaseHalf(b, from, QueueKind::Graphics);
        if (!release.srcStages) release.srcStages = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
        const int32_t source = lastPassOn(from);
        if (source >= 0) releaseAfterFamily(source, from, b, release.srcStages);
        schedule_.releases.push_back({source, release});
        b.srcQueue = release.srcQueue;
        b.dstQueue = QueueKind::Graphics;
        if (!b.srcStages) b.srcStages = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
        return b;
    }

    int32_t lastPassOn(size_t queue) const {
        for (size_t i = schedule_.queues.size(); i-- > 0;)
            if (slot(schedule_.queues[i]) == queue) return static_cast<int32_t>(i);
        return kFrameStart;
    }

    const GraphDesc& graph_;
    const GraphIndex& index_;
    const CompileOptions& options_;
    Plan& plan_;
    QueueSchedule schedule_;
    std::vector<uint8_t> exclusive_;
    std::vector<SubresourceGrid> grids_;
    std::vector<uint32_t> firstCell_{0};
    std::vector<Cell> cells_;
    struct LaterReads {
        uint32_t resource;
        VkPipelineStageFlags2 stages;
        VkAccessFlags2 access;
    };
    std::vector<std::vector<LaterReads>> laterReads_;  // per pass: gatherLaterReadsOnTheQueue
    std::vector<std::array<int32_t, kQueueKinds>> lastUseOf_;  // per resource and queue
    std::vector<std::array<VkPipelineStageFlags2, kQueueKinds>> useStagesOf_;
    std::array<bool, kQueueKinds> startedQueue_{};
    std::array<std::array<std::vector<std::pair<int32_t, VkPipelineStageFlags2>>, kQueueKinds>, kQueueKinds> waited_;
};

}  // namespace

void planQueues(const GraphIndex& index, const CompileOptions& options, Plan& plan) {
    QueuePlanner(index, options, plan).run();
}

}  // namespace skygraph
