// The path tracer's view of a scene's glTF meshes: every triangle of every model in one BVH,
// and the arrays pathtrace.comp reads (std430 layouts), built on the CPU once per set of
// models. Textures travel as texels in a storage buffer, each with a table entry: the shader
// filters them itself (bilinear, mip 0), so it needs no array of samplers, which Vulkan lets a
// dispatch index per invocation only with descriptor indexing (lavapipe lacks it).
#pragma once

#include "triangle_bvh.hpp"

#include <skygraph/triangle_mesh.hpp>

#include <memory>
#include <vector>

namespace skygraph::passes {

struct TraceVertex {  // `Vertex` in pathtrace.comp
    float positionU[4];
    float normalV[4];
    float tangent[4];
};

struct TraceMaterial {  // `Material` in pathtrace.comp
    float baseColor[4];
    float emissiveRoughness[4];
    float metallicNormalScaleAlpha[4];  ///< metallic, normal scale (0: none), alpha threshold (< 0: opaque)
    int32_t textures[4];                ///< base colour, metallic-roughness, normal, emissive: entries of
                                        ///< TraceGeometry::textures; -1 none
};

/// `Texture` in pathtrace.comp: where an image's texels start in TraceGeometry::texels, its
/// size, and how it is read.
struct TraceTextureEntry {
    uint32_t firstTexel = 0;
    uint32_t width = 0, height = 0;
    uint32_t flags = 0;  ///< bits 0-1: wrapS, 2-3: wrapT (MeshWrap), 4: sRGB
};

struct TraceGeometry {
    std::vector<std::shared_ptr<const TriangleMesh>> models;
    std::vector<BvhNode> nodes;
    std::vector<uint32_t> triangles;  ///< 4 per triangle: vertices (into `vertices`), material
    std::vector<TraceVertex> vertices;
    std::vector<TraceMaterial> materials;
    std::vector<TraceTextureEntry> textures;
    std::vector<uint32_t> texels;  ///< RGBA8, R in the low byte; each image once
    uint32_t bvhDepth = 0;
};

/// Flattens `models` (world space already) into one geometry. Throws std::length_error,
/// naming the model's file, when the texels would pass 2^32.
[[nodiscard]] TraceGeometry buildTraceGeometry(std::vector<std::shared_ptr<const TriangleMesh>> models);

}  // namespace skygraph::passes
