// The synchronization-point graph: chains, closure, and where accesses sit in it.
#include "happens_before.hpp"

#include <algorithm>

namespace skygraph::verifier {
namespace {

bool queueOrdersFirstSide(SyncPoint::Kind k) { return k != SyncPoint::Kind::SemaphoreWait; }
bool queueOrdersSecondSide(SyncPoint::Kind k) { return k != SyncPoint::Kind::SemaphoreSignal; }

/// In-pass barriers order only the two halves of a ReadWrite transfer of their step.
bool inPassExcludes(const SyncPoint& p, const QueuePlace& a) {
    return p.inPassStep >= 0 && p.inPassStep == a.step && a.outsideInPassOrder;
}

}  // namespace

bool PointSet::any() const {
    return std::any_of(words_.begin(), words_.end(), [](uint64_t w) { return w != 0; });
}

bool PointSet::intersects(const PointSet& o) const {
    const size_t n = std::min(words_.size(), o.words_.size());
    for (size_t i = 0; i < n; ++i)
        if (words_[i] & o.words_[i]) return true;
    return false;
}

PointSet& PointSet::operator|=(const PointSet& o) {
    if (words_.size() < o.words_.size()) words_.resize(o.words_.size(), 0);
    for (size_t i = 0; i < o.words_.size(); ++i) words_[i] |= o.words_[i];
    return *this;
}

PointId HappensBefore::add(const SyncPoint& point) {
    points_.push_back(point);
    edges_.emplace_back();
    return static_cast<PointId>(points_.size() - 1);
}

void HappensBefore::addEdge(PointId from, PointId to) { edges_.at(from).push_back(to); }

bool HappensBefore::chains(const SyncPoint& from, const SyncPoint& to) const {
    if (from.queue != to.queue || from.position >= to.position || from.batch == to.batch) return false;
    if (!queueOrdersSecondSide(from.kind) || !queueOrdersFirstSide(to.kind)) return false;
    return from.secondSync.intersects(to.firstSync) || allDeviceStages().within(to.firstSync);
}

void HappensBefore::finalize() {
    for (PointId a = 0; a < points_.size(); ++a)
        for (PointId b = 0; b < points_.size(); ++b)
            if (chains(points_[a], points_[b])) edges_[a].push_back(b);
    closure_.assign(points_.size(), PointSet(points_.size()));
    std::vector<uint8_t> state(points_.size(), 0);
    for (PointId p = 0; p < points_.size(); ++p) close(p, state);
}

// Depth-first, memoized; the graph is acyclic (edges go forward in time), and a point being
// visited again is simply not followed, so a malformed graph cannot loop.
void HappensBefore::close(PointId p, std::vector<uint8_t>& state) {
    if (state[p]) return;
    state[p] = 1;
    for (PointId q : edges_[p]) {
        close(q, state);
        closure_[p].set(q);
        closure_[p] |= closure_[q];
    }
    state[p] = 2;
}

AccessPlace HappensBefore::onQueue(const QueuePlace& a) const {
    AccessPlace place{PointSet(points_.size()), PointSet(points_.size())};
    if (a.stages.empty()) return place;  // an access at no stage is ordered by nothing
    for (PointId p = 0; p < points_.size(); ++p) {
        const SyncPoint& s = points_[p];
        if (s.queue != a.queue || inPassExcludes(s, a)) continue;
        if (s.position > a.position && queueOrdersFirstSide(s.kind) && a.stages.within(s.firstSync))
            place.enters.set(p);
        if (s.position < a.position && queueOrdersSecondSide(s.kind) && a.stages.within(s.secondSync))
            place.after.set(p);
    }
    return place;
}

AccessPlace HappensBefore::inside(PointId barrier) const {
    AccessPlace place{PointSet(points_.size()), PointSet(points_.size())};
    place.enters.set(barrier);
    place.after.set(barrier);
    return place;
}

AccessPlace HappensBefore::between(PointId release, PointId acquire) const {
    AccessPlace place{PointSet(points_.size()), PointSet(points_.size())};
    place.enters.set(acquire);
    place.after.set(release);
    return place;
}

AccessPlace HappensBefore::waitingFor(PointId signal, StageSet stages) const {
    AccessPlace place{PointSet(points_.size()), PointSet(points_.size())};
    place.after.set(signal);
    const SyncPoint& s = points_.at(signal);
    if (stages.empty()) return place;
    for (PointId p = 0; p < points_.size(); ++p) {
        const SyncPoint& q = points_[p];
        if (q.queue == s.queue && q.position < s.position && queueOrdersSecondSide(q.kind) &&
            stages.within(q.secondSync))
            place.after.set(p);
    }
    return place;
}

AccessPlace HappensBefore::signalling(PointId wait) const {
    AccessPlace place{PointSet(points_.size()), PointSet(points_.size())};
    place.enters.set(wait);
    return place;
}

PointSet HappensBefore::withSuccessors(const PointSet& set) const {
    PointSet out = set;
    set.forEach([&](uint32_t p) { out |= closure_.at(p); });
    return out;
}

bool HappensBefore::happensBefore(const AccessPlace& earlier, const AccessPlace& later) const {
    return withSuccessors(earlier.enters).intersects(later.after);
}

}  // namespace skygraph::verifier
