// A bounding volume hierarchy over triangles, built on the CPU for the path tracer's shader
// (pathtrace.comp walks it with a stack). Binned SAH: each split is the cheapest of 12
// candidate planes per axis, by surface area times triangles; a node keeps at most
// kMaxLeafTriangles, or more only where no plane separates their centroids.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace skygraph::passes {

/// std430-ready: 32 bytes. A leaf has count > 0 and covers triangles[first, first + count);
/// an interior node has count == 0 and children first and first + 1.
struct BvhNode {
    float min[3];
    uint32_t first;
    float max[3];
    uint32_t count;
};
static_assert(sizeof(BvhNode) == 32);

struct TriangleBvh {
    std::vector<BvhNode> nodes;       ///< nodes[0] is the root (absent for no triangles)
    std::vector<uint32_t> triangles;  ///< triangle numbers, each once, in leaf order
    uint32_t depth = 0;               ///< levels from the root to the deepest leaf, root = 1
};

inline constexpr uint32_t kMaxLeafTriangles = 4;
/// The shader's traversal stack holds this many nodes; the build never goes deeper.
inline constexpr uint32_t kMaxBvhDepth = 48;

using TriangleCorners = std::array<std::array<float, 3>, 3>;

/// Builds the hierarchy over `triangles` (triangle t is triangles[t]). Degenerate triangles
/// are kept: the shader's test rejects them.
[[nodiscard]] TriangleBvh buildTriangleBvh(std::span<const TriangleCorners> triangles);

}  // namespace skygraph::passes
