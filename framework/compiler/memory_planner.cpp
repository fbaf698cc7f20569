// Placement of transient resources (docs/memory.md): heaps by memory type, then one of the
// strategies, then which earlier resources each one takes memory over from. A 10,000-pass
// frame has some 15,000 transients and its whole compile takes a few milliseconds, so every
// phase costs in proportion to the resources and the steps each holds memory for (best fit
// also to the resources live beside each), and allocates up front.
#include "memory_planner.hpp"

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <vector>

namespace skygraph {
namespace {

constexpr uint32_t kNone = ~0u;

uint64_t alignUp(uint64_t v, uint64_t a) { return (v + a - 1) & ~(a - 1); }

/// One input, as the strategies see it: in its heap, with the size and alignment it is placed
/// with, and the steps it holds its memory for.
struct Item {
    uint64_t bytes = 0;
    uint64_t alignment = 1;
    uint64_t offset = 0;
    uint32_t heap = 0;
    uint32_t first = 0, last = 0;  ///< Held; the whole frame when it may not share.
};

/// Resources go to the first heap whose memory types they can live in too; the heap keeps the
/// types all its resources can. Heaps holding buffers and images together place on
/// bufferImageGranularity.
std::vector<Item> assignHeaps(std::span<const TransientResource> in, uint32_t steps, uint64_t granularity,
                              bool aliasing, std::vector<MemoryHeap>& heaps) {
    std::vector<Item> items(in.size());
    std::vector<uint8_t> kinds;  // per heap: bit 0 linear, bit 1 optimal
    for (size_t i = 0; i < in.size(); ++i) {
        const TransientResource& t = in[i];
        const uint32_t bits = t.requirements.memoryTypeBits;
        uint32_t h = 0;
        while (h < heaps.size() && (heaps[h].memoryTypeBits & bits) == 0) ++h;
        if (h == heaps.size()) {
            heaps.push_back({0, bits, false});
            kinds.push_back(0);
        }
        heaps[h].memoryTypeBits &= bits;
        kinds[h] |= static_cast<uint8_t>(t.linear ? 1 : 2);
        const bool shares = aliasing && t.aliasable;
        items[i] = {t.requirements.size, std::max<uint64_t>(1, t.requirements.alignment), 0, h,
                    shares ? t.firstStep : 0, shares ? t.lastStep : steps - 1};
    }
    bool anyGranular = false;
    for (size_t h = 0; h < heaps.size(); ++h) anyGranular |= heaps[h].granular = kinds[h] == 3 && granularity > 1;
    if (anyGranular)
        for (Item& it : items)
            if (heaps[it.heap].granular) {
                it.alignment = std::max(it.alignment, granularity);
                it.bytes = alignUp(it.bytes, granularity);
            }
    return items;
}

/// Each in turn after the last: no sharing.
void placeUnaliased(std::vector<Item>& items, std::vector<MemoryHeap>& heaps) {
    for (Item& it : items) {
        it.offset = alignUp(heaps[it.heap].bytes, it.alignment);
        heaps[it.heap].bytes = it.offset + it.bytes;
    }
}

/// Item indices by size, largest first, then in order of first use. Frames have few distinct
/// sizes (the same formats at the same fractions of the output), so items are counted into
/// one bucket per size; a frame with many falls back to sorting.
std::vector<uint32_t> largestFirst(const std::vector<Item>& items) {
    constexpr size_t kMostBuckets = 32;
    std::vector<uint64_t> sizes;
    std::vector<uint32_t> count;
    std::vector<uint8_t> bucketOf(items.size());
    size_t last = 0;
    for (size_t i = 0; i < items.size(); ++i) {
        const uint64_t b = items[i].bytes;
        if (last >= sizes.size() || sizes[last] != b) {
            last = std::find(sizes.begin(), sizes.end(), b) - sizes.begin();
            if (last == sizes.size()) {
                if (sizes.size() == kMostBuckets) {
                    std::vector<uint32_t> order(items.size());
                    for (uint32_t j = 0; j < order.size(); ++j) order[j] = j;
                    std::stable_sort(order.begin(), order.end(),
                                     [&](uint32_t x, uint32_t y) { return items[x].bytes > items[y].bytes; });
                    return order;
                }
                sizes.push_back(b);
                count.push_back(0);
            }
        }
        bucketOf[i] = static_cast<uint8_t>(last);
        ++count[last];
    }
    std::vector<uint32_t> rank(sizes.size());
    for (uint32_t j = 0; j < rank.size(); ++j) rank[j] = j;
    std::sort(rank.begin(), rank.end(), [&](uint32_t x, uint32_t y) { return sizes[x] > sizes[y]; });
    std::vector<uint32_t> start(sizes.size());
    uint32_t at = 0;
    for (const uint32_t r : rank) {
        start[r] = at;
        at += count[r];
    }
    std::vector<uint32_t> order(items.size());
    for (uint32_t i = 0; i < items.size(); ++i) order[start[bucketOf[i]]++] = i;
    return order;
}

/// Largest first; each goes into the smallest gap that fits between the resources already
/// placed in its heap that hold memory during any step it does (above them all if none fits),
/// as AMD's Render Pipeline Shaders place theirs.
void placeBestFitBySize(std::vector<Item>& items, std::vector<MemoryHeap>& heaps, uint32_t steps) {
    // Resources that hold memory for a few steps are found through linked lists per step, in
    // one array sized up front and left unwritten until used. Each step has two lists: the
    // items whose memory is first held there, and those held since an earlier step. An item
    // holding steps f..l meets every placed item it shares a step with once: those held at f,
    // and those first held in f+1..l.
    struct Node {
        uint64_t begin, end;
        uint32_t next;
    };
    // Longer-lived ones (those that may not share hold the whole frame) are kept apart, per
    // heap by offset: a node per step for each would make a frame of many long-lived
    // resources (one pass reading thousands) quadratic in memory, and sorting them for every
    // item that meets them, cubic in time.
    constexpr uint32_t kShortLife = 16;
    const auto isLong = [](const Item& it) { return it.last - it.first >= kShortLife; };
    size_t nodeCount = 0;
    for (const Item& it : items) nodeCount += isLong(it) ? 0 : it.last - it.first + 1;
    const std::unique_ptr<Node[]> nodes(new Node[nodeCount]);
    struct Held {
        uint64_t begin, end;
        uint32_t first, last;
    };
    std::vector<std::vector<Held>> longLived(heaps.size());  // per heap, by offset
    // Out of line: the common loop below keeps its registers.
    const auto keepByOffset = [](std::vector<Held>& to, Held held) __attribute__((noinline)) {
        to.insert(std::upper_bound(to.begin(), to.end(), held.begin,
                                   [](uint64_t offset, const Held& x) { return offset < x.begin; }),
                  held);
    };
    // Per heap and step: [2 * step] the items first held there, [2 * step + 1] those held since before.
    std::vector<uint32_t> head(2 * size_t(steps) * heaps.size(), kNone);
    uint32_t used = 0;
    // The intervals an item lives beside, kept sorted by offset as they are gathered (few
    // short-lived ones are live at once: insertion beats a sort call). No item meets more
    // than every other.
    struct Busy {
        uint64_t begin, end;
    };
    const std::unique_ptr<Busy[]> busy(new Busy[items.size()]);
    size_t busyCount = 0;
    const auto add = [&](Busy b) {
        size_t at = busyCount++;
        for (; at > 0 && b.begin < busy[at - 1].begin; --at) busy[at] = busy[at - 1];
        busy[at] = b;
    };
    const auto gather = [&](uint32_t list) {
        for (uint32_t n = list; n != kNone; n = nodes[n].next) add({nodes[n].begin, nodes[n].end});
    };
    for (const uint32_t i : largestFirst(items)) {
        Item& it = items[i];
        // The long-lived ones it shares a step with come in order of offset, and the
        // short-lived ones are inserted among them.
        busyCount = 0;
        for (const Held& h : longLived[it.heap])
            if (h.first <= it.last && h.last >= it.first) busy[busyCount++] = {h.begin, h.end};
        uint32_t* lists = head.data() + 2 * size_t(it.heap) * steps;
        gather(lists[2 * it.first]);
        gather(lists[2 * it.first + 1]);
        for (uint32_t s = it.first + 1; s <= it.last; ++s) gather(lists[2 * s]);
        uint64_t free = 0, best = ~uint64_t(0), bestGap = ~uint64_t(0);
        for (size_t b = 0; b < busyCount; ++b) {
            const uint64_t start = alignUp(free, it.alignment);
            if (start + it.bytes <= busy[b].begin && busy[b].begin - start < bestGap) {
                best = start;
                bestGap = busy[b].begin - start;
            }
            free = std::max(free, busy[b].end);
        }
        it.offset = bestGap != ~uint64_t(0) ? best : alignUp(free, it.alignment);
        heaps[it.heap].bytes = std::max(heaps[it.heap].bytes, it.offset + it.bytes);
        if (isLong(it)) {
            keepByOffset(longLived[it.heap], {it.offset, it.offset + it.bytes, it.first, it.last});
            continue;
        }
        for (uint32_t s = it.first; s <= it.last; ++s) {
            uint32_t& list = lists[2 * s + (s == it.first ? 0 : 1)];
            nodes[used] = {it.offset, it.offset + it.bytes, list};
            list = used++;
        }
    }
}

/// In order of first use; before each, the memory of resources whose last use is past goes
/// back to its heap's free blocks, and it takes the smallest free block that fits (or the
/// heap grows). Resources that may not share never take a free block and never give back.
void placeFirstUseOrder(std::vector<Item>& items, std::vector<MemoryHeap>& heaps, uint32_t steps) {
    struct Block {
        uint64_t begin, end;
    };
    std::vector<std::vector<Block>> freeBlocks(heaps.size());  // per heap, by offset, coalesced
    std::vector<uint32_t> endingAt(steps, kNone), nextEnding(items.size(), kNone);
    const auto release = [&](uint32_t heap, Block b) {
        auto& blocks = freeBlocks[heap];
        auto at = std::lower_bound(blocks.begin(), blocks.end(), b.begin,
                                   [](const Block& x, uint64_t v) { return x.begin < v; });
        if (at != blocks.end() && at->begin == b.end) {
            b.end = at->end;
            at = blocks.erase(at);
        }
        if (at != blocks.begin() && std::prev(at)->end == b.begin) {
            std::prev(at)->end = b.end;
            return;
        }
        blocks.insert(at, b);
    };
    uint32_t released = 0;  // steps whose ending resources have been released
    for (uint32_t i = 0; i < items.size(); ++i) {
        Item& it = items[i];
        const bool shares = !(it.first == 0 && it.last == steps - 1);
        for (; released < it.first; ++released)
            for (uint32_t j = endingAt[released]; j != kNone; j = nextEnding[j])
                release(items[j].heap, {items[j].offset, items[j].offset + items[j].bytes});
        auto& blocks = freeBlocks[it.heap];
        size_t best = blocks.size();
        for (size_t b = 0; shares && b < blocks.size(); ++b) {
            const uint64_t start = alignUp(blocks[b].begin, it.alignment);
            if (start + it.bytes > blocks[b].end) continue;
            if (best == blocks.size() || blocks[b].end - blocks[b].begin < blocks[best].end - blocks[best].begin)
                best = b;
        }
        uint64_t& top = heaps[it.heap].bytes;
        if (best < blocks.size()) {
            const Block b = blocks[best];
            it.offset = alignUp(b.begin, it.alignment);
            // What the resource leaves of the block, below and above it.
            const Block below{b.begin, it.offset}, above{it.offset + it.bytes, b.end};
            if (below.begin < below.end && above.begin < above.end) {
                blocks[best] = below;
                blocks.insert(blocks.begin() + static_cast<std::ptrdiff_t>(best) + 1, above);
            } else if (below.begin < below.end) {
                blocks[best] = below;
            } else if (above.begin < above.end) {
                blocks[best] = above;
            } else {
                blocks.erase(blocks.begin() + static_cast<std::ptrdiff_t>(best));
            }
        } else if (shares && !blocks.empty() && blocks.back().end == top) {
            // The free block at the top grows into the space it needs.
            it.offset = alignUp(blocks.back().begin, it.alignment);
            const uint64_t begin = blocks.back().begin;
            blocks.pop_back();
            if (begin < it.offset) blocks.push_back({begin, it.offset});
            top = it.offset + it.bytes;
        } else {
            it.offset = alignUp(top, it.alignment);
            if (shares && top < it.offset) release(it.heap, {top, it.offset});
            top = it.offset + it.bytes;
        }
        if (shares) {
            nextEnding[i] = endingAt[it.last];
            endingAt[it.last] = i;
        }
    }
}

/// Sorts storage[first..], one placement's aliases of one kind, and drops repeats. Inlined:
/// as a call it costs the sweep 2% of a 10k-pass compile.
[[gnu::always_inline]] inline void sortRun(std::vector<uint32_t>& storage, size_t first) {
    if (storage.size() - first < 2) return;
    std::sort(storage.begin() + static_cast<std::ptrdiff_t>(first), storage.end());
    storage.erase(std::unique(storage.begin() + static_cast<std::ptrdiff_t>(first), storage.end()), storage.end());
}

/// Where a placement's aliases start in the layout's storage, and how many of each kind.
struct AliasRun {
    uint32_t inFrameFirst = 0, inFrame = 0;
    uint32_t previousFrameFirst = 0, previousFrame = 0;
};

/// For each resource in order of first use, the resources that last held each byte of its
/// range: a sweep over each heap's bytes, kept as segments by their latest holder. Appends
/// them to `storage`, sorted. With frames sharing the heaps, the bytes a resource finds held
/// by nobody earlier in the frame were last held by whoever holds them when the frame ends:
/// those ranges are kept during the sweep and looked up in the segments it leaves, which
/// name the previous-frame aliases (appended after every in-frame run, each sorted).
std::vector<AliasRun> findAliases(std::span<const TransientResource> in, const std::vector<Item>& items,
                                  size_t heapCount, bool acrossFrames, std::vector<uint32_t>& storage) {
    struct Segment {
        uint64_t begin, end;
        uint32_t holder;  // index into items
    };
    struct Unheld {  // bytes of an item that no earlier item of the frame held
        uint64_t begin, end;
        uint32_t item;
    };
    std::vector<std::vector<Segment>> heldBy(heapCount);
    std::vector<AliasRun> runs(items.size());
    std::vector<Unheld> unheld;
    const auto firstOverlapping = [](std::vector<Segment>& segments, uint64_t begin) {
        return std::partition_point(segments.begin(), segments.end(),
                                    [&](const Segment& seg) { return seg.end <= begin; });
    };
    for (uint32_t i = 0; i < items.size(); ++i) {
        const Item& it = items[i];
        auto& segments = heldBy[it.heap];
        const uint64_t begin = it.offset, end = it.offset + it.bytes;
        const auto from = firstOverlapping(segments, begin);
        auto to = from;
        const auto first = static_cast<uint32_t>(storage.size());
        uint64_t covered = begin;  // the bytes below it are held by earlier items
        for (; to != segments.end() && to->begin < end; ++to) {
            // Placement never lets two resources that live at the same time share a byte.
            if (in[to->holder].lastStep >= in[i].firstStep)
                throw std::logic_error("memory planner: plan resources " + std::to_string(in[to->holder].resource) +
                                       " and " + std::to_string(in[i].resource) + " share memory while both live");
            storage.push_back(in[to->holder].resource);
            if (acrossFrames && to->begin > covered) unheld.push_back({covered, to->begin, i});
            covered = std::max(covered, to->end);
        }
        if (acrossFrames && covered < end) unheld.push_back({covered, end, i});
        sortRun(storage, first);
        runs[i] = {first, static_cast<uint32_t>(storage.size()) - first, 0, 0};
        // The resource now holds [begin, end); what the segments it overlaps held outside
        // it stays theirs.
        if (to - from == 1 && from->begin == begin && from->end == end) {
            from->holder = i;  // the common case: the same range as the last holder
            continue;
        }
        Segment replacement[3];
        size_t n = 0;
        if (from != to && from->begin < begin) replacement[n++] = {from->begin, begin, from->holder};
        replacement[n++] = {begin, end, i};
        if (from != to && std::prev(to)->end > end) replacement[n++] = {end, std::prev(to)->end, std::prev(to)->holder};
        const auto at = static_cast<size_t>(from - segments.begin());
        const auto old = static_cast<size_t>(to - from);
        if (n <= old) {
            std::copy(replacement, replacement + n, segments.begin() + static_cast<std::ptrdiff_t>(at));
            segments.erase(segments.begin() + static_cast<std::ptrdiff_t>(at + n),
                           segments.begin() + static_cast<std::ptrdiff_t>(at + old));
        } else {
            std::copy(replacement, replacement + old, segments.begin() + static_cast<std::ptrdiff_t>(at));
            segments.insert(segments.begin() + static_cast<std::ptrdiff_t>(at + old), replacement + old,
                            replacement + n);
        }
    }
    // The segments now say who holds each byte as the frame ends: the previous frame left
    // the same. `unheld` is in item order.
    for (size_t u = 0; u < unheld.size();) {
        const uint32_t i = unheld[u].item;
        auto& segments = heldBy[items[i].heap];
        const auto first = static_cast<uint32_t>(storage.size());
        for (; u < unheld.size() && unheld[u].item == i; ++u)
            for (auto seg = firstOverlapping(segments, unheld[u].begin);
                 seg != segments.end() && seg->begin < unheld[u].end; ++seg)
                storage.push_back(in[seg->holder].resource);
        sortRun(storage, first);
        runs[i].previousFrameFirst = first;
        runs[i].previousFrame = static_cast<uint32_t>(storage.size()) - first;
    }
    return runs;
}

}  // namespace

MemoryLayout placeTransients(std::span<const TransientResource> in, uint32_t steps, uint64_t granularity,
                             MemoryStrategy strategy, bool aliasing, bool acrossFrames) {
    MemoryLayout out;
    out.granularity = granularity;
    out.sharedAcrossFrames = acrossFrames;
    if (!aliasing) strategy = MemoryStrategy::Unaliased;
    aliasing = strategy != MemoryStrategy::Unaliased;
    out.strategy = strategy;
    if (in.empty()) return out;
    std::vector<Item> items = assignHeaps(in, steps, granularity, aliasing, out.heaps);
    switch (strategy) {
        case MemoryStrategy::Unaliased: placeUnaliased(items, out.heaps); break;
        case MemoryStrategy::BestFitBySize: placeBestFitBySize(items, out.heaps, steps); break;
        case MemoryStrategy::FirstUseOrder: placeFirstUseOrder(items, out.heaps, steps); break;
    }
    // Without aliasing, frames sharing the heaps still take over each other's bytes. Found
    // first, so that the placements are written once, with their aliases' final storage.
    std::vector<AliasRun> runs;
    std::vector<uint32_t>& storage = detail::MemoryLayoutBuilder::aliasStorage(out);
    if (aliasing || acrossFrames) {
        storage.reserve(in.size() * (acrossFrames ? 2 : 1));
        runs = findAliases(in, items, out.heaps.size(), acrossFrames, storage);
    }
    out.placements.reserve(in.size());
    // The lower bound: resources that may not share hold memory all frame, whatever the strategy.
    std::vector<int64_t> liveChange(size_t(steps) + 1, 0);
    for (size_t i = 0; i < in.size(); ++i) {
        MemoryPlacement& p = out.placements.emplace_back();
        p.resource = in[i].resource;
        p.heap = items[i].heap;
        p.offset = items[i].offset;
        p.bytes = items[i].bytes;
        p.requirements = in[i].requirements;
        p.aliasable = aliasing && in[i].aliasable;
        if (!runs.empty()) {
            p.aliases = {storage.data() + runs[i].inFrameFirst, runs[i].inFrame};
            p.previousFrameAliases = {storage.data() + runs[i].previousFrameFirst, runs[i].previousFrame};
        }
        out.unaliasedBytes += items[i].bytes;
        const uint32_t first = in[i].aliasable ? in[i].firstStep : 0;
        const uint32_t last = in[i].aliasable ? in[i].lastStep : steps - 1;
        liveChange[first] += static_cast<int64_t>(items[i].bytes);
        liveChange[last + 1] -= static_cast<int64_t>(items[i].bytes);
    }
    int64_t live = 0;
    for (uint32_t s = 0; s < steps; ++s) {
        live += liveChange[s];
        out.peakLiveBytes = std::max(out.peakLiveBytes, static_cast<uint64_t>(live));
    }
    return out;
}

}  // namespace skygraph
