// The builder of the frame model (frame_model.hpp), split over files by what it records:
// frame_model.cpp the frames and their memory objects, frame_commands.cpp what the queue
// records (barrier batches and usages), frame_outside.cpp the agents outside the queue (the
// presentation engine, the host, and readers of external and exported resources).
#pragma once

#include "frame_model.hpp"
#include "frame_resources.hpp"

#include <string>
#include <vector>

namespace skygraph::verifier {

/// How an access is placed among the points, resolved once every point exists.
struct PlaceSpec {
    enum class Kind : uint8_t { Queue, Inside, Between, WaitingFor, Signalling };
    Kind kind = Kind::Queue;
    QueuePlace queue;
    PointId point = 0;
    StageSet stages;
    PointId release = 0;  ///< Between: the release; `point` is the acquire.
};

class FrameBuilder {
public:
    FrameBuilder(const Plan& plan, const GraphDesc& graph, const VerifyOptions& options, Reporter& reporter,
                 FrameModel& model)
        : plan_(plan), graph_(graph), options_(options), reporter_(reporter), model_(model) {}

    void run();

private:
    /// A presented image of this frame: its Presentation and its memory object.
    struct Presented {
        const Presentation* presentation;
        uint32_t object;
    };
    struct BatchEntry {
        PointId point;
        const Barrier* barrier;
        uint32_t object;
    };

    // frame_model.cpp
    void makeObjects();
    void recordFrame(uint32_t f);
    /// Submit `k` of frame f on its queue: its waits, passes, releases, (last) final barriers
    /// and signal.
    void recordSubmit(uint32_t f, size_t k);
    void recordWaits(uint32_t f, size_t k);
    void recordSignals(uint32_t f, size_t k);
    /// Semaphore signal-to-wait edges of every frame, once all points exist.
    void linkSemaphores();
    /// Step i: its barrier batch, usages and in-pass barriers.
    void recordStep(uint32_t f, size_t i);
    FindingSite submitSite(uint32_t frame, size_t k, std::string what) const;
    void checkQueueStages(uint32_t f, const FindingSite& site, const char* side, VkPipelineStageFlags2 stages,
                          int64_t resource = -1);
    void resolvePlaces();
    /// Each transfer's release happens before its acquire (once the graph is final).
    void checkTransfersOrdered();
    /// The object of plan resource `r` in frame `f`, or -1 (reported when `r` is out of range).
    int32_t objectOf(uint32_t f, uint32_t r, const FindingSite& site);
    void addAccess(ModelAccess a, PlaceSpec spec);
    PointId addPoint(const SyncPoint& p, const BarrierMemory& memory);
    /// Mask problems of one side of a barrier or usage (reported in the first frame only).
    void checkMask(uint32_t f, const FindingSite& site, int64_t resource, const char* side,
                   VkPipelineStageFlags2 stages, VkAccessFlags2 access);
    void report(FindingKind kind, FindingSite site, std::string reason, int64_t resource = -1);
    FindingSite stepSite(uint32_t frame, size_t step, std::string what) const;

    // frame_commands.cpp
    /// `releases`: the batch holds the release halves of ownership transfers, whose layout
    /// transitions happen in their acquire halves.
    void recordBatch(uint32_t f, size_t step, const std::vector<const Barrier*>& barriers, int64_t inPassStep,
                     const char* label, uint64_t position, bool releases = false);
    void markWholeObjects(const std::vector<BatchEntry>& entries);
    /// The step's usages; returns the timeline items of the ReadWrite transfers' copies in,
    /// which come after the in-pass barriers.
    std::vector<TimelineItem> recordUsages(uint32_t f, size_t step, uint64_t position);
    void recordInPassBatch(uint32_t f, size_t step, uint64_t position);
    void recordReadbackCopy(uint32_t f, size_t step, size_t usage, const QueuePlace& q);

    // frame_outside.cpp
    std::vector<Presented> recordAcquires(uint32_t f);
    void recordAcquireWaits(QueueKind queue, uint64_t batch, bool waited);
    void recordPresentsAndFence(uint32_t f, const std::vector<Presented>& presented);
    void recordOutsideReadsBefore(uint32_t f);
    void recordOutsideReadsAfter(uint32_t f);
    void recordOutsideRead(uint32_t f, uint32_t r, const RequiredScope& scope, int64_t step, const char* what);

    const Plan& plan_;
    const GraphDesc& graph_;
    const VerifyOptions& options_;
    Reporter& reporter_;
    FrameModel& model_;
    std::vector<ResourceShape> shapes_;
    std::vector<PlaceSpec> pending_;     // per access: how to place it once the points exist
    std::vector<uint32_t> hostCopies_;   // this frame's read-back copies, which the host reads
    /// This frame's presentation engine reads (their accesses) whose acquire wait is not yet recorded.
    struct AcquireRead {
        const Presentation* presentation;
        size_t access;
    };
    std::vector<AcquireRead> acquireReads_;
    uint64_t position_ = 0, batch_ = 0;  // submission order; batches, which never chain within
    QueueKind queue_ = QueueKind::Graphics;  // of the submit being recorded
    /// Per frame, the semaphore operations recorded: signals and waits by semaphore and value.
    struct SemaphorePoint {
        uint32_t frame;
        QueueKind semaphore;
        uint32_t value;
        PointId point;
        size_t submit;
    };
    std::vector<SemaphorePoint> signals_, waits_;
    /// Releases recorded and not yet acquired: what an acquire's transition happens after.
    struct PendingRelease {
        uint32_t object;
        QueueKind from, to;
        SubresourceRange range;  ///< Images.
        PointId point;
        FindingSite site;
        uint32_t frame;
    };
    std::vector<PendingRelease> releases_;
    /// The ownership transfers of the first frame: the release must happen before the acquire.
    struct Transfer {
        PointId release, acquire;
        FindingSite releaseSite, acquireSite;
        uint32_t resource;
        bool transition;  ///< A layout transition happens between the halves.
    };
    std::vector<Transfer> transfers_;
};

}  // namespace skygraph::verifier
