// Placement of transient resources (docs/memory.md): heaps by memory type, then one of the
// strategies, then which earlier resources each one takes memory over from.
#include "memory_planner.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace skygraph {
namespace {

constexpr uint32_t kNone = ~0u;

uint64_t alignUp(uint64_t v, uint64_t a) { return (v + a - 1) & ~(a - 1); }

/// One input, as the strategies see it: in its heap, with the size and alignment it is placed
/// with, and the steps it holds its memory for.
struct Item {
    uint32_t heap = 0;
    uint64_t bytes = 0;
    uint64_t alignment = 1;
    uint32_t first = 0, last = 0;  ///< Held; the whole frame when it may not share.
    uint64_t offset = 0;
};

/// Resources go to the first heap whose memory types they can live in too; the heap keeps the
/// types all its resources can. Heaps holding buffers and images together place on
/// bufferImageGranularity.
std::vector<Item> assignHeaps(std::span<const TransientResource> in, uint32_t steps, uint64_t granularity,
                              bool aliasing, std::vector<MemoryHeap>& heaps) {
    std::vector<Item> items(in.size());
    std::vector<uint8_t> kinds;  // per heap: bit 0 linear, bit 1 optimal
    for (size_t i = 0; i < in.size(); ++i) {
        const uint32_t bits = in[i].requirements.memoryTypeBits;
        uint32_t h = 0;
        while (h < heaps.size() && (heaps[h].memoryTypeBits & bits) == 0) ++h;
        if (h == heaps.size()) {
            heaps.push_back({0, bits, false});
            kinds.push_back(0);
        }
        heaps[h].memoryTypeBits &= bits;
        kinds[h] |= static_cast<uint8_t>(in[i].linear ? 1 : 2);
        Item& it = items[i];
        it.heap = h;
        it.bytes = in[i].requirements.size;
        it.alignment = std::max<uint64_t>(1, in[i].requirements.alignment);
        const bool shares = aliasing && in[i].aliasable;
        it.first = shares ? in[i].firstStep : 0;
        it.last = shares ? in[i].lastStep : steps - 1;
    }
    for (size_t h = 0; h < heaps.size(); ++h) heaps[h].granular = kinds[h] == 3 && granularity > 1;
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

/// Largest first; each goes into the smallest gap that fits between the resources already
/// placed in its heap that hold memory during any step it does (above them all if none fits).
void placeBestFitBySize(std::vector<Item>& items, std::vector<MemoryHeap>& heaps, uint32_t steps) {
    std::vector<uint32_t> order(items.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        if (items[a].bytes != items[b].bytes) return items[a].bytes > items[b].bytes;
        return a < b;  // inputs come in order of first use
    });
    // The placed items holding memory at each step, as linked lists in one array.
    struct Node {
        uint32_t item, next;
    };
    std::vector<uint32_t> head(steps, kNone);
    std::vector<Node> nodes;
    std::vector<uint32_t> seen(items.size(), kNone);
    struct Busy {
        uint64_t begin, end;
    };
    std::vector<Busy> busy;
    for (const uint32_t i : order) {
        Item& it = items[i];
        busy.clear();
        for (uint32_t s = it.first; s <= it.last; ++s)
            for (uint32_t n = head[s]; n != kNone; n = nodes[n].next) {
                const uint32_t j = nodes[n].item;
                if (seen[j] == i || items[j].heap != it.heap) continue;
                seen[j] = i;
                busy.push_back({items[j].offset, items[j].offset + items[j].bytes});
            }
        std::sort(busy.begin(), busy.end(), [](const Busy& a, const Busy& b) { return a.begin < b.begin; });
        uint64_t free = 0, best = kNone, bestGap = ~uint64_t(0);
        for (const Busy& b : busy) {
            const uint64_t start = alignUp(free, it.alignment);
            if (start + it.bytes <= b.begin && b.begin - start < bestGap) {
                best = start;
                bestGap = b.begin - start;
            }
            free = std::max(free, b.end);
        }
        it.offset = best != kNone ? best : alignUp(free, it.alignment);
        heaps[it.heap].bytes = std::max(heaps[it.heap].bytes, it.offset + it.bytes);
        for (uint32_t s = it.first; s <= it.last; ++s) {
            nodes.push_back({i, head[s]});
            head[s] = static_cast<uint32_t>(nodes.size() - 1);
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
    const auto release = [&](const Item& it) {
        auto& blocks = freeBlocks[it.heap];
        Block b{it.offset, it.offset + it.bytes};
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
            for (uint32_t j = endingAt[released]; j != kNone; j = nextEnding[j]) release(items[j]);
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
            blocks.erase(blocks.begin() + static_cast<std::ptrdiff_t>(best));
            std::vector<Block> rest;
            if (b.begin < it.offset) rest.push_back({b.begin, it.offset});
            if (it.offset + it.bytes < b.end) rest.push_back({it.offset + it.bytes, b.end});
            blocks.insert(blocks.begin() + static_cast<std::ptrdiff_t>(best), rest.begin(), rest.end());
        } else if (shares && !blocks.empty() && blocks.back().end == top) {
            // The free block at the top grows into the space it needs.
            it.offset = alignUp(blocks.back().begin, it.alignment);
            const uint64_t begin = blocks.back().begin;
            blocks.pop_back();
            if (begin < it.offset) blocks.push_back({begin, it.offset});
            top = it.offset + it.bytes;
        } else {
            it.offset = alignUp(top, it.alignment);
            if (shares && top < it.offset) release(Item{it.heap, it.offset - top, 1, 0, 0, top});
            top = it.offset + it.bytes;
        }
        if (shares) {
            nextEnding[i] = endingAt[it.last];
            endingAt[it.last] = i;
        }
    }
}

/// For each resource in order of first use, the resources that last held each byte of its
/// range: a sweep over each heap's bytes, kept as segments by their latest holder.
void findAliases(std::span<const TransientResource> in, const std::vector<Item>& items, size_t heapCount,
                 std::vector<MemoryPlacement>& placements) {
    struct Segment {
        uint64_t begin, end;
        uint32_t holder;  // index into items
    };
    std::vector<std::vector<Segment>> heldBy(heapCount);
    std::vector<Segment> replaced;
    for (uint32_t i = 0; i < items.size(); ++i) {
        const Item& it = items[i];
        auto& segments = heldBy[it.heap];
        const uint64_t begin = it.offset, end = it.offset + it.bytes;
        auto from = std::partition_point(segments.begin(), segments.end(), [&](const Segment& s) { return s.end <= begin; });
        auto to = from;
        std::vector<uint32_t>& aliases = placements[i].aliases;
        for (; to != segments.end() && to->begin < end; ++to) {
            const uint32_t holder = to->holder;
            // Placement never lets two resources that live at the same time share a byte.
            if (in[holder].lastStep >= in[i].firstStep)
                throw std::logic_error("memory planner: '" + std::to_string(in[holder].resource) + "' and '" +
                                       std::to_string(in[i].resource) + "' share memory while both live");
            aliases.push_back(in[holder].resource);
        }
        replaced.clear();
        if (from != to && from->begin < begin) replaced.push_back({from->begin, begin, from->holder});
        replaced.push_back({begin, end, i});
        if (from != to && std::prev(to)->end > end) replaced.push_back({end, std::prev(to)->end, std::prev(to)->holder});
        const auto at = segments.erase(from, to);
        segments.insert(at, replaced.begin(), replaced.end());
        std::sort(aliases.begin(), aliases.end());
        aliases.erase(std::unique(aliases.begin(), aliases.end()), aliases.end());
    }
}

}  // namespace

MemoryLayout placeTransients(std::span<const TransientResource> in, uint32_t steps, uint64_t granularity,
                             MemoryStrategy strategy, bool aliasing) {
    MemoryLayout out;
    out.granularity = granularity;
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
    out.placements.resize(in.size());
    // The lower bound: resources that may not share hold memory all frame, whatever the strategy.
    std::vector<int64_t> liveChange(size_t(steps) + 1, 0);
    for (size_t i = 0; i < in.size(); ++i) {
        MemoryPlacement& p = out.placements[i];
        p.resource = in[i].resource;
        p.heap = items[i].heap;
        p.offset = items[i].offset;
        p.bytes = items[i].bytes;
        p.requirements = in[i].requirements;
        p.aliasable = aliasing && in[i].aliasable;
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
    if (aliasing) findAliases(in, items, out.heaps.size(), out.placements);
    return out;
}

}  // namespace skygraph
