// The path tracer's CPU side, without a device: the BVH (every triangle once, boxes that hold
// what they cover, nearest hits equal to a brute-force search) and the flattened geometry
// (vertices, materials and texture entries as pathtrace.comp reads them).
#include "path_trace/trace_geometry.hpp"
#include "path_trace/triangle_bvh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

namespace skygraph::passes {
namespace {

using Vec = std::array<float, 3>;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
float dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Möller-Trumbore, as the shader.
std::optional<float> hit(const TriangleCorners& t, const Vec& o, const Vec& d) {
    const Vec e1 = sub(t[1], t[0]), e2 = sub(t[2], t[0]), p = cross(d, e2);
    const float det = dot(e1, p);
    if (std::abs(det) < 1e-20f) return std::nullopt;
    const Vec s = sub(o, t[0]);
    const float u = dot(s, p) / det;
    if (u < 0 || u > 1) return std::nullopt;
    const Vec q = cross(s, e1);
    const float v = dot(d, q) / det;
    if (v < 0 || u + v > 1) return std::nullopt;
    const float dist = dot(e2, q) / det;
    return dist > 0 ? std::optional<float>(dist) : std::nullopt;
}

bool boxHit(const BvhNode& n, const Vec& o, const Vec& d, float tMax) {
    float enter = 0, leave = tMax;
    for (int a = 0; a < 3; ++a) {
        const float t0 = (n.min[a] - o[a]) / d[a], t1 = (n.max[a] - o[a]) / d[a];
        enter = std::max(enter, std::min(t0, t1));
        leave = std::min(leave, std::max(t0, t1));
    }
    return enter <= leave;
}

/// The nearest triangle through the BVH, walked as the shader walks it.
std::optional<std::pair<float, uint32_t>> nearestThroughBvh(const TriangleBvh& bvh, std::span<const TriangleCorners> tris,
                                                            const Vec& o, const Vec& d) {
    std::optional<std::pair<float, uint32_t>> best;
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
        const BvhNode n = bvh.nodes[stack.back()];
        stack.pop_back();
        if (!boxHit(n, o, d, best ? best->first : 3.4e38f)) continue;
        if (n.count == 0) {
            stack.push_back(n.first);
            stack.push_back(n.first + 1);
            continue;
        }
        for (uint32_t i = n.first; i < n.first + n.count; ++i)
            if (const auto t = hit(tris[bvh.triangles[i]], o, d); t && (!best || *t < best->first))
                best = std::make_pair(*t, bvh.triangles[i]);
    }
    return best;
}

std::vector<TriangleCorners> randomTriangles(size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> centre(-10.0f, 10.0f), offset(-0.8f, 0.8f);
    std::vector<TriangleCorners> tris(n);
    for (auto& t : tris) {
        const Vec c{centre(rng), centre(rng), centre(rng)};
        for (auto& corner : t) corner = {c[0] + offset(rng), c[1] + offset(rng), c[2] + offset(rng)};
    }
    return tris;
}

TEST(TriangleBvh, CoversEveryTriangleOnceInBoxesThatHoldThem) {
    const auto tris = randomTriangles(2000, 7);
    const TriangleBvh bvh = buildTriangleBvh(tris);
    std::vector<uint32_t> sorted = bvh.triangles;
    std::sort(sorted.begin(), sorted.end());
    for (uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
    EXPECT_LE(bvh.depth, kMaxBvhDepth);
    EXPECT_GE(bvh.depth, 9u) << "2000 triangles in leaves of at most 4 need at least 9 levels";
    size_t leaves = 0;
    const auto inside = [](const BvhNode& outer, const float* lo, const float* hi) {
        for (int a = 0; a < 3; ++a)
            if (lo[a] < outer.min[a] || hi[a] > outer.max[a]) return false;
        return true;
    };
    for (const BvhNode& n : bvh.nodes) {
        if (n.count == 0) {
            ASSERT_LT(n.first + 1, bvh.nodes.size());
            EXPECT_TRUE(inside(n, bvh.nodes[n.first].min, bvh.nodes[n.first].max));
            EXPECT_TRUE(inside(n, bvh.nodes[n.first + 1].min, bvh.nodes[n.first + 1].max));
            continue;
        }
        ++leaves;
        EXPECT_LE(n.count, kMaxLeafTriangles);
        for (uint32_t i = n.first; i < n.first + n.count; ++i)
            for (const auto& c : tris[bvh.triangles[i]]) EXPECT_TRUE(inside(n, c.data(), c.data()));
    }
    EXPECT_GE(leaves, 2000u / kMaxLeafTriangles);
}

TEST(TriangleBvh, FindsTheNearestHitABruteForceSearchFinds) {
    const auto tris = randomTriangles(3000, 11);
    const TriangleBvh bvh = buildTriangleBvh(tris);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    size_t hits = 0;
    for (int r = 0; r < 2000; ++r) {
        const Vec o{u(rng) * 15, u(rng) * 15, u(rng) * 15};
        Vec d{u(rng), u(rng), u(rng)};
        const float len = std::sqrt(dot(d, d));
        for (float& x : d) x /= len;
        std::optional<std::pair<float, uint32_t>> brute;
        for (uint32_t t = 0; t < tris.size(); ++t)
            if (const auto h = hit(tris[t], o, d); h && (!brute || *h < brute->first)) brute = std::make_pair(*h, t);
        const auto viaBvh = nearestThroughBvh(bvh, tris, o, d);
        ASSERT_EQ(brute.has_value(), viaBvh.has_value()) << "ray " << r;
        if (brute) {
            ++hits;
            EXPECT_EQ(brute->second, viaBvh->second) << "ray " << r;
        }
    }
    EXPECT_GT(hits, 200u) << "enough rays must hit for the comparison to mean something";
}

TEST(TriangleBvh, TrianglesWithOneCentroidShareALeafAndNoTrianglesNoNodes) {
    std::vector<TriangleCorners> same(10, TriangleCorners{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
    const TriangleBvh bvh = buildTriangleBvh(same);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.nodes[0].count, 10u);
    EXPECT_TRUE(buildTriangleBvh({}).nodes.empty());
}

TEST(TraceGeometry, FlattensModelsAndSharesAnImageBetweenItsEntries) {
    auto mesh = std::make_shared<TriangleMesh>();
    for (float x : {0.0f, 1.0f})
        for (float z : {0.0f, 1.0f}) mesh->vertices.push_back({{x, 0, z}, {0, 1, 0}, {x, z}, {1, 0, 0, 1}});
    mesh->indices = {0, 1, 2, 1, 3, 2};
    MeshPrimitive p;
    p.indexCount = 6;
    p.material.baseColor = {0.5, 0.25, 1.0, 0.5};
    p.material.alphaMode = MeshAlphaMode::Mask;
    p.material.alphaCutoff = 0.25;
    p.material.baseColorTexture.image = 0;
    p.material.normalTexture = {0, MeshWrap::ClampToEdge, MeshWrap::MirroredRepeat};
    p.material.normalScale = 0.5;
    mesh->primitives = {p};
    mesh->images.push_back({2, 1, {1, 2, 3, 4, 5, 6, 7, 8}, "images[0]"});
    // The same model twice (two scene objects): its vertices twice, its image's texels too.
    const TraceGeometry g = buildTraceGeometry({mesh, mesh});
    ASSERT_EQ(g.vertices.size(), 8u);
    EXPECT_EQ(g.vertices[1].positionU[3], 0.0f);  // (1, 0, 0): u = 1... of vertex (x=0, z=1): u 0, v 1
    EXPECT_EQ(g.vertices[1].normalV[3], 1.0f);
    ASSERT_EQ(g.triangles.size(), 4u * 4u);
    ASSERT_EQ(g.materials.size(), 2u);
    for (size_t t = 0; t < 4; ++t) {
        const uint32_t material = g.triangles[t * 4 + 3];
        for (int k = 0; k < 3; ++k) EXPECT_EQ(g.triangles[t * 4 + size_t(k)] / 4, material) << "its own model's vertices";
    }
    const TraceMaterial& m = g.materials[0];
    EXPECT_FLOAT_EQ(m.metallicNormalScaleAlpha[1], 0.5f);
    EXPECT_FLOAT_EQ(m.metallicNormalScaleAlpha[2], 0.5f) << "cutoff / the factor's alpha";
    EXPECT_EQ(m.textures[1], -1);
    EXPECT_EQ(m.textures[3], -1);
    ASSERT_GE(m.textures[0], 0);
    ASSERT_GE(m.textures[2], 0);
    const TraceTextureEntry& base = g.textures[size_t(m.textures[0])];
    const TraceTextureEntry& normal = g.textures[size_t(m.textures[2])];
    EXPECT_EQ(base.firstTexel, normal.firstTexel) << "one image, read two ways";
    EXPECT_EQ(base.flags, 16u) << "repeat, repeat, sRGB";
    EXPECT_EQ(normal.flags, uint32_t(MeshWrap::ClampToEdge) | uint32_t(MeshWrap::MirroredRepeat) << 2);
    EXPECT_EQ(base.width, 2u);
    EXPECT_EQ(g.textures.size(), 4u) << "two entries per model";
    ASSERT_EQ(g.texels.size(), 4u) << "each model's image once";
    EXPECT_EQ(g.texels[0], 0x04030201u) << "R in the low byte";
}

}  // namespace
}  // namespace skygraph::passes
