// Placement of transient resources (framework/compiler/memory_planner.cpp), on inputs written
// here: what shares memory and what never may, heaps, granularity, the figures, and which
// earlier resources each one takes memory over from. A seeded property test checks every
// strategy's layouts against the definitions by brute force.
#include "memory_planner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>
#include <set>
#include <vector>

namespace skygraph {
namespace {

std::vector<uint32_t> ids(std::span<const uint32_t> aliases) { return {aliases.begin(), aliases.end()}; }

TransientResource image(uint32_t r, uint32_t first, uint32_t last, uint64_t size, uint64_t alignment = 256) {
    return {r, first, last, {size, alignment, 1u}, false, true};
}

bool overlapsInMemory(const MemoryPlacement& a, const MemoryPlacement& b) {
    return a.heap == b.heap && a.offset < b.offset + b.bytes && b.offset < a.offset + a.bytes;
}

bool overlapsInTime(const TransientResource& a, const TransientResource& b) {
    return a.firstStep <= b.lastStep && b.firstStep <= a.lastStep;
}

constexpr MemoryStrategy kSharing[] = {MemoryStrategy::BestFitBySize, MemoryStrategy::FirstUseOrder};

TEST(MemoryPlacement, DisjointLifetimesShareAndTheLaterTakesOverFromTheEarlier) {
    const std::vector<TransientResource> in = {image(0, 0, 1, 1024), image(1, 2, 3, 1024)};
    for (const MemoryStrategy s : kSharing) {
        const MemoryLayout m = placeTransients(in, 4, 1024, s, true);
        ASSERT_EQ(m.placements.size(), 2u);
        EXPECT_EQ(m.placements[0].offset, m.placements[1].offset) << toString(s);
        EXPECT_EQ(m.heapBytes(), 1024u);
        EXPECT_EQ(m.unaliasedBytes, 2048u);
        EXPECT_EQ(m.peakLiveBytes, 1024u);
        EXPECT_TRUE(m.placements[0].aliases.empty());
        EXPECT_EQ(ids(m.placements[1].aliases), std::vector<uint32_t>{0});
    }
}

// A copy views its own alias storage, not the original's (which may be gone), except where a
// caller pointed a placement at storage of its own: that stays as it was.
TEST(MemoryPlacement, ACopyViewsItsOwnAliasStorage) {
    const std::vector<TransientResource> in = {image(0, 0, 1, 1024), image(1, 2, 3, 1024)};
    auto original = std::make_unique<MemoryLayout>(placeTransients(in, 4, 1024, MemoryStrategy::BestFitBySize, true));
    const std::vector<uint32_t> callers{7};
    original->placements[0].aliases = callers;
    const MemoryLayout copy = *original;
    EXPECT_NE(copy.placements[1].aliases.data(), original->placements[1].aliases.data());
    EXPECT_EQ(copy.placements[0].aliases.data(), callers.data());
    original.reset();
    EXPECT_EQ(ids(copy.placements[1].aliases), std::vector<uint32_t>{0});
    EXPECT_EQ(ids(copy.placements[0].aliases), std::vector<uint32_t>{7});
}

TEST(MemoryPlacement, OverlappingLifetimesNeverShare) {
    // Lifetimes are inclusive: a resource last used in step 2 and one first used there overlap.
    const std::vector<TransientResource> in = {image(0, 0, 2, 1024), image(1, 2, 3, 1024)};
    for (const MemoryStrategy s : kSharing) {
        const MemoryLayout m = placeTransients(in, 4, 1024, s, true);
        EXPECT_FALSE(overlapsInMemory(m.placements[0], m.placements[1])) << toString(s);
        EXPECT_EQ(m.heapBytes(), 2048u);
        EXPECT_EQ(m.peakLiveBytes, 2048u);
        EXPECT_TRUE(m.placements[1].aliases.empty());
    }
}

TEST(MemoryPlacement, NoAliasingAndNotAliasableResourcesGetRangesOfTheirOwn) {
    std::vector<TransientResource> in = {image(0, 0, 0, 1000), image(1, 1, 1, 1000), image(2, 2, 2, 1000)};
    const MemoryLayout off = placeTransients(in, 3, 1024, MemoryStrategy::BestFitBySize, false);
    EXPECT_EQ(off.strategy, MemoryStrategy::Unaliased);
    EXPECT_EQ(off.heapBytes(), 1024u + 1024u + 1000u);  // each aligned after the last
    for (const MemoryPlacement& p : off.placements) {
        EXPECT_TRUE(p.aliases.empty());
        EXPECT_FALSE(p.aliasable);
    }
    EXPECT_EQ(off.peakLiveBytes, 1000u) << "the lower bound does not depend on the strategy";

    in[1].aliasable = false;  // "alias": false
    for (const MemoryStrategy s : kSharing) {
        const MemoryLayout m = placeTransients(in, 3, 1024, s, true);
        EXPECT_FALSE(overlapsInMemory(m.placements[0], m.placements[1])) << toString(s);
        EXPECT_FALSE(overlapsInMemory(m.placements[2], m.placements[1])) << toString(s);
        EXPECT_TRUE(overlapsInMemory(m.placements[0], m.placements[2])) << toString(s);
        EXPECT_EQ(ids(m.placements[2].aliases), std::vector<uint32_t>{0});
        EXPECT_EQ(m.peakLiveBytes, 2000u) << "a resource that may not share holds memory all frame";
    }
}

TEST(MemoryPlacement, BuffersAndImagesTogetherArePlacedOnTheGranularity) {
    std::vector<TransientResource> in = {image(0, 0, 0, 1000, 256), image(1, 1, 1, 3000, 512)};
    in.push_back({2, 2, 2, {100, 16, 1u}, true, true});  // a buffer: the spec's linear resource
    for (const MemoryStrategy s : kSharing) {
        const MemoryLayout m = placeTransients(in, 3, 4096, s, true);
        ASSERT_EQ(m.heaps.size(), 1u);
        EXPECT_TRUE(m.heaps[0].granular);
        for (const MemoryPlacement& p : m.placements) {
            EXPECT_EQ(p.offset % 4096, 0u) << toString(s);
            EXPECT_EQ(p.bytes % 4096, 0u) << toString(s);
        }
    }
    in.pop_back();
    const MemoryLayout images = placeTransients(in, 3, 4096, MemoryStrategy::BestFitBySize, true);
    EXPECT_FALSE(images.heaps[0].granular) << "optimal images alone alias on their own alignment";
    EXPECT_EQ(images.placements[1].bytes, 3000u);
}

TEST(MemoryPlacement, ResourcesGoToHeapsOfMemoryTypesTheyCanLiveIn) {
    std::vector<TransientResource> in = {image(0, 0, 0, 1024), image(1, 1, 1, 1024), image(2, 2, 2, 1024)};
    in[0].requirements.memoryTypeBits = 0b0011;
    in[1].requirements.memoryTypeBits = 0b0100;  // no type in common with the first
    in[2].requirements.memoryTypeBits = 0b0010;
    const MemoryLayout m = placeTransients(in, 3, 1024, MemoryStrategy::BestFitBySize, true);
    ASSERT_EQ(m.heaps.size(), 2u);
    EXPECT_EQ(m.placements[0].heap, 0u);
    EXPECT_EQ(m.placements[1].heap, 1u);
    EXPECT_EQ(m.placements[2].heap, 0u);
    EXPECT_EQ(m.heaps[0].memoryTypeBits, 0b0010u) << "the types both of its resources can live in";
    EXPECT_EQ(ids(m.placements[2].aliases), std::vector<uint32_t>{0});
}

TEST(MemoryPlacement, AliasesAreTheLastHoldersOfEachByte) {
    // 0 and 1 side by side, then 2 over both, then 3 over the first half of 2 only.
    const std::vector<TransientResource> in = {image(0, 0, 0, 1024), image(1, 0, 0, 1024), image(2, 1, 1, 2048),
                                               image(3, 2, 2, 1024)};
    const MemoryLayout m = placeTransients(in, 3, 1024, MemoryStrategy::BestFitBySize, true);
    EXPECT_EQ(ids(m.placements[2].aliases), (std::vector<uint32_t>{0, 1}));
    EXPECT_EQ(ids(m.placements[3].aliases), std::vector<uint32_t>{2}) << "0 and 1 are ordered before it through 2";
}

TEST(MemoryPlacement, BestFitFillsAGapBeforeGrowingTheHeap) {
    // p lives in steps 0-1, r in step 0 above it, q in 1-2 above p too; s (step 2) fits in
    // the gap p leaves below q, where the top of the heap would grow it. (Inputs come in
    // order of first use.)
    const std::vector<TransientResource> in = {image(0, 0, 1, 4096), image(1, 0, 0, 1024), image(2, 1, 2, 2048),
                                               image(3, 2, 2, 1024)};
    const MemoryLayout m = placeTransients(in, 3, 1024, MemoryStrategy::BestFitBySize, true);
    EXPECT_EQ(m.placements[2].offset, 4096u);
    EXPECT_EQ(m.placements[3].offset, 0u);
    EXPECT_EQ(m.heapBytes(), 6144u);
    EXPECT_EQ(ids(m.placements[3].aliases), std::vector<uint32_t>{0});
}

TEST(MemoryPlacement, EmptyInput) {
    const MemoryLayout m = placeTransients({}, 0, 1024, MemoryStrategy::BestFitBySize, true);
    EXPECT_TRUE(m.heaps.empty());
    EXPECT_EQ(m.heapBytes(), 0u);
}

/// The definitions, checked by brute force on one layout.
void expectValid(const std::vector<TransientResource>& in, uint32_t steps, const MemoryLayout& m,
                 uint64_t granularity, const std::string& what) {
    ASSERT_EQ(m.placements.size(), in.size()) << what;
    uint64_t peak = 0;
    for (uint32_t s = 0; s < steps; ++s) {
        uint64_t live = 0;
        for (size_t i = 0; i < in.size(); ++i)
            if ((in[i].aliasable ? in[i].firstStep : 0) <= s && s <= (in[i].aliasable ? in[i].lastStep : steps - 1))
                live += m.placements[i].bytes;
        peak = std::max(peak, live);
    }
    EXPECT_EQ(m.peakLiveBytes, peak) << what;
    EXPECT_GE(m.heapBytes(), m.peakLiveBytes) << what;
    for (size_t i = 0; i < in.size(); ++i) {
        const MemoryPlacement& p = m.placements[i];
        EXPECT_EQ(p.offset % in[i].requirements.alignment, 0u) << what;
        EXPECT_GE(p.bytes, in[i].requirements.size) << what;
        EXPECT_LE(p.offset + p.bytes, m.heaps[p.heap].bytes) << what;
        if (m.heaps[p.heap].granular) {
            EXPECT_EQ(p.offset % granularity, 0u) << what;
        }
        std::vector<uint32_t> expectedAliases;
        for (size_t j = 0; j < in.size(); ++j) {
            if (i == j || !overlapsInMemory(p, m.placements[j])) continue;
            ASSERT_FALSE(overlapsInTime(in[i], in[j])) << what << ": " << i << " and " << j << " share while live";
            ASSERT_TRUE(in[i].aliasable && in[j].aliasable) << what;
            // j is an alias of i if it held a byte of i's last before i's first use.
            if (in[j].lastStep >= in[i].firstStep) continue;
            bool lastHolder = false;
            for (uint64_t b = std::max(p.offset, m.placements[j].offset);
                 b < std::min(p.offset + p.bytes, m.placements[j].offset + m.placements[j].bytes) && !lastHolder; b += 64) {
                bool later = false;
                for (size_t k = 0; k < in.size() && !later; ++k)
                    later = k != i && k != j && m.placements[k].heap == p.heap && m.placements[k].offset <= b &&
                            b < m.placements[k].offset + m.placements[k].bytes && in[k].firstStep > in[j].lastStep &&
                            in[k].lastStep < in[i].firstStep;
                lastHolder = !later;
            }
            if (lastHolder) expectedAliases.push_back(in[j].resource);
        }
        std::sort(expectedAliases.begin(), expectedAliases.end());
        EXPECT_EQ(ids(p.aliases), expectedAliases) << what << ": resource " << i;
        if (!m.sharedAcrossFrames) {
            EXPECT_TRUE(p.previousFrameAliases.empty()) << what;
            continue;
        }
        // With frames sharing the heaps, a byte no earlier resource of the frame held was last
        // held, in the previous frame, by the last resource (in first-use order) that holds it.
        std::set<uint32_t> previous;
        for (uint64_t b = p.offset; b < p.offset + p.bytes; b += 64) {
            bool heldInFrame = false;
            for (size_t j = 0; j < i && !heldInFrame; ++j)
                heldInFrame = m.placements[j].heap == p.heap && m.placements[j].offset <= b &&
                              b < m.placements[j].offset + m.placements[j].bytes;
            if (heldInFrame) continue;
            for (size_t j = in.size(); j-- > 0;)
                if (m.placements[j].heap == p.heap && m.placements[j].offset <= b &&
                    b < m.placements[j].offset + m.placements[j].bytes) {
                    previous.insert(in[j].resource);
                    break;
                }
        }
        EXPECT_EQ(ids(p.previousFrameAliases), std::vector<uint32_t>(previous.begin(), previous.end()))
            << what << ": resource " << i << ", previous frame";
    }
}

TEST(MemoryPlacement, RandomInputsMeetTheDefinitionsUnderEveryStrategy) {
    for (uint32_t seed = 1; seed <= 300; ++seed) {
        std::mt19937 rng(seed);
        const auto steps = static_cast<uint32_t>(1 + rng() % 12);
        std::vector<TransientResource> in;
        const auto count = static_cast<uint32_t>(1 + rng() % 14);
        for (uint32_t i = 0; i < count; ++i) {
            auto a = static_cast<uint32_t>(rng() % steps), b = static_cast<uint32_t>(rng() % steps);
            if (a > b) std::swap(a, b);
            TransientResource t = image(i, a, b, 64 * (1 + rng() % 64), 64u << (rng() % 4));
            t.linear = rng() % 5 == 0;
            t.aliasable = rng() % 7 != 0;
            t.requirements.memoryTypeBits = rng() % 6 == 0 ? 2u : 3u;
            in.push_back(t);
        }
        std::stable_sort(in.begin(), in.end(), [](const auto& x, const auto& y) { return x.firstStep < y.firstStep; });
        for (uint32_t i = 0; i < in.size(); ++i) in[i].resource = i;
        for (const MemoryStrategy s : {MemoryStrategy::BestFitBySize, MemoryStrategy::FirstUseOrder,
                                       MemoryStrategy::Unaliased}) {
            for (const bool acrossFrames : {false, true}) {
                const MemoryLayout m = placeTransients(in, steps, 256, s, true, acrossFrames);
                expectValid(in, steps, m, 256,
                            "seed " + std::to_string(seed) + " " + toString(s) + (acrossFrames ? " shared" : ""));
                EXPECT_EQ(m, placeTransients(in, steps, 256, s, true, acrossFrames)) << "deterministic";
            }
        }
    }
}

/// Best fit by size by brute force: largest first (equal sizes in first-use order), each at the
/// smallest gap that fits among the placed resources it shares a step with, else above them
/// all. Images in one heap (no granularity).
std::vector<uint64_t> bestFitOffsets(const std::vector<TransientResource>& in) {
    std::vector<uint32_t> order(in.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t x, uint32_t y) { return in[x].requirements.size > in[y].requirements.size; });
    std::vector<uint64_t> offset(in.size());
    std::vector<bool> placed(in.size());
    for (const uint32_t i : order) {
        std::vector<std::pair<uint64_t, uint64_t>> busy;
        for (size_t j = 0; j < in.size(); ++j)
            if (placed[j] && overlapsInTime(in[i], in[j])) busy.emplace_back(offset[j], offset[j] + in[j].requirements.size);
        std::sort(busy.begin(), busy.end());
        const uint64_t alignment = in[i].requirements.alignment, bytes = in[i].requirements.size;
        const auto alignUp = [&](uint64_t v) { return (v + alignment - 1) / alignment * alignment; };
        uint64_t free = 0, best = 0, bestGap = ~uint64_t(0);
        for (const auto& [begin, end] : busy) {
            const uint64_t start = alignUp(free);
            if (start + bytes <= begin && begin - start < bestGap) {
                best = start;
                bestGap = begin - start;
            }
            free = std::max(free, end);
        }
        offset[i] = bestGap != ~uint64_t(0) ? best : alignUp(free);
        placed[i] = true;
    }
    return offset;
}

// Resources that hold memory for many steps are looked up apart from the short-lived ones
// (memory_planner.cpp): best fit places both as its definition says, and a frame where one
// pass reads thousands of resources stays linear in memory.
TEST(MemoryPlacement, BestFitPlacesLongAndShortLivedResourcesByItsDefinition) {
    for (uint32_t seed = 1; seed <= 100; ++seed) {
        std::mt19937 rng(seed);
        const auto steps = static_cast<uint32_t>(20 + rng() % 200);
        const auto count = static_cast<uint32_t>(1 + rng() % 200);
        std::vector<TransientResource> in;
        for (uint32_t i = 0; i < count; ++i) {
            const auto first = static_cast<uint32_t>(rng() % steps);
            const uint32_t span = rng() % 2 ? static_cast<uint32_t>(rng() % 6) : static_cast<uint32_t>(rng() % steps);
            in.push_back(image(i, first, std::min(steps - 1, first + span), 256 * (1 + rng() % 6), 256u << (rng() % 3)));
        }
        std::stable_sort(in.begin(), in.end(), [](const auto& x, const auto& y) { return x.firstStep < y.firstStep; });
        for (uint32_t i = 0; i < in.size(); ++i) in[i].resource = i;
        const MemoryLayout m = placeTransients(in, steps, 1024, MemoryStrategy::BestFitBySize, true);
        const std::vector<uint64_t> expected = bestFitOffsets(in);
        ASSERT_EQ(m.placements.size(), in.size());
        for (size_t i = 0; i < in.size(); ++i)
            ASSERT_EQ(m.placements[i].offset, expected[i]) << "seed " << seed << ", resource " << i;
        expectValid(in, steps, m, 1024, "seed " + std::to_string(seed));
    }
}

// The device-free estimate (docs/memory.md, "Requirements"), on the sizes the shipped graphs use.
TEST(MemoryEstimate, ImagesArePackedTexelsInPagesAndBuffersTheirSize) {
    const auto model = estimatedMemory();
    ResourceDesc hdr;
    hdr.format = *findFormat("R16G16B16A16_SFLOAT");
    MemoryQuery q;
    q.resource = &hdr;
    q.width = 1920;
    q.height = 1080;
    EXPECT_EQ(model->requirements(q), (MemoryRequirements{16646144, 65536, 1u})) << "1920 x 1080 x 8 bytes, in 64 KiB";
    ResourceDesc cube;
    cube.type = ResourceType::Cube;
    cube.format = *findFormat("R16G16B16A16_SFLOAT");
    q.resource = &cube;
    q.width = q.height = 256;
    q.mips = 9;
    q.layers = 6;
    // 6 faces of 256^2 + 128^2 + ... + 1 texels of 8 bytes: 6 x 699048 bytes, in 64 KiB pages.
    EXPECT_EQ(model->requirements(q).size, 4194304u);
    ResourceDesc buffer;
    buffer.type = ResourceType::Buffer;
    buffer.sizeBytes = 100;
    q.resource = &buffer;
    EXPECT_EQ(model->requirements(q), (MemoryRequirements{100, 256, 1u}));
    EXPECT_EQ(model->bufferImageGranularity(), 1024u);
    EXPECT_EQ(model->name(), "estimate");
}

}  // namespace
}  // namespace skygraph
