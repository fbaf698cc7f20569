#include "triangle_bvh.hpp"

#include <algorithm>
#include <limits>

namespace skygraph::passes {
namespace {

struct Box {
    std::array<float, 3> lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::max()};
    std::array<float, 3> hi{std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest(),
                            std::numeric_limits<float>::lowest()};
    void grow(const std::array<float, 3>& p) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    }
    void grow(const Box& b) {
        if (b.empty()) return;  // its corners are the opposite infinities
        grow(b.lo);
        grow(b.hi);
    }
    [[nodiscard]] bool empty() const { return lo[0] > hi[0]; }
    [[nodiscard]] float area() const {
        if (empty()) return 0.0f;
        const float x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
        return 2.0f * (x * y + y * z + z * x);
    }
};

constexpr int kBins = 12;

class Builder {
public:
    explicit Builder(std::span<const TriangleCorners> triangles) : triangles_(triangles) {
        bounds_.resize(triangles.size());
        centroids_.resize(triangles.size());
        for (size_t t = 0; t < triangles.size(); ++t) {
            for (const auto& corner : triangles[t]) bounds_[t].grow(corner);
            for (int a = 0; a < 3; ++a)
                centroids_[t][a] = (triangles[t][0][a] + triangles[t][1][a] + triangles[t][2][a]) / 3.0f;
        }
    }

    TriangleBvh build() {
        TriangleBvh bvh;
        if (triangles_.empty()) return bvh;
        bvh.triangles.resize(triangles_.size());
        for (uint32_t t = 0; t < bvh.triangles.size(); ++t) bvh.triangles[t] = t;
        bvh.nodes.push_back({});
        split(bvh, 0, 0, uint32_t(triangles_.size()), 1);
        return bvh;
    }

private:
    void split(TriangleBvh& bvh, uint32_t node, uint32_t first, uint32_t count, uint32_t depth) {
        bvh.depth = std::max(bvh.depth, depth);
        Box box, centroidBox;
        for (uint32_t i = first; i < first + count; ++i) {
            box.grow(bounds_[bvh.triangles[i]]);
            centroidBox.grow(centroids_[bvh.triangles[i]]);
        }
        const auto makeLeaf = [&] {
            BvhNode& n = bvh.nodes[node];
            for (int a = 0; a < 3; ++a) {
                n.min[a] = box.lo[a];
                n.max[a] = box.hi[a];
            }
            n.first = first;
            n.count = count;
        };
        if (count <= kMaxLeafTriangles || depth >= kMaxBvhDepth) return makeLeaf();
        // The cheapest plane among kBins - 1 per axis, binned by centroid.
        float bestCost = std::numeric_limits<float>::max();
        int bestAxis = -1, bestPlane = 0;
        for (int a = 0; a < 3; ++a) {
            const float lo = centroidBox.lo[a], extent = centroidBox.hi[a] - lo;
            if (!(extent > 0.0f)) continue;
            std::array<Box, kBins> bins;
            std::array<uint32_t, kBins> counts{};
            for (uint32_t i = first; i < first + count; ++i) {
                const uint32_t t = bvh.triangles[i];
                const int b = binOf(centroids_[t][a], lo, extent);
                bins[size_t(b)].grow(bounds_[t]);
                ++counts[size_t(b)];
            }
            std::array<float, kBins> rightCost{};
            Box right;
            uint32_t rightCount = 0;
            for (int b = kBins - 1; b > 0; --b) {
                right.grow(bins[size_t(b)]);
                rightCount += counts[size_t(b)];
                rightCost[size_t(b)] = right.area() * float(rightCount);
            }
            Box left;
            uint32_t leftCount = 0;
            for (int b = 0; b < kBins - 1; ++b) {
                left.grow(bins[size_t(b)]);
                leftCount += counts[size_t(b)];
                const float cost = left.area() * float(leftCount) + rightCost[size_t(b + 1)];
                if (leftCount > 0 && leftCount < count && cost < bestCost) {
                    bestCost = cost;
                    bestAxis = a;
                    bestPlane = b;
                }
            }
        }
        if (bestAxis < 0) return makeLeaf();  // every centroid in one point
        const float lo = centroidBox.lo[bestAxis], extent = centroidBox.hi[bestAxis] - lo;
        const auto middle = std::partition(bvh.triangles.begin() + first, bvh.triangles.begin() + first + count,
                                           [&](uint32_t t) { return binOf(centroids_[t][bestAxis], lo, extent) <= bestPlane; });
        const auto leftCount = uint32_t(middle - (bvh.triangles.begin() + first));
        const auto children = uint32_t(bvh.nodes.size());
        bvh.nodes.push_back({});
        bvh.nodes.push_back({});
        BvhNode& n = bvh.nodes[node];
        for (int a = 0; a < 3; ++a) {
            n.min[a] = box.lo[a];
            n.max[a] = box.hi[a];
        }
        n.first = children;
        n.count = 0;
        split(bvh, children, first, leftCount, depth + 1);
        split(bvh, children + 1, first + leftCount, count - leftCount, depth + 1);
    }

    static int binOf(float c, float lo, float extent) {
        return std::clamp(int(float(kBins) * (c - lo) / extent), 0, kBins - 1);
    }

    std::span<const TriangleCorners> triangles_;
    std::vector<Box> bounds_;
    std::vector<std::array<float, 3>> centroids_;
};

}  // namespace

TriangleBvh buildTriangleBvh(std::span<const TriangleCorners> triangles) { return Builder(triangles).build(); }

}  // namespace skygraph::passes
