// Triangle meshes from glTF 2.0 files (.gltf and .glb, read with tinygltf): what a scene's
// `{"type": "gltf"}` object holds. The loader flattens the file's default scene: every mesh
// instance is placed in world space (its node hierarchy and the scene object's transform
// applied), so drawing needs no per-node matrices.
#pragma once

#include <skygraph/diagnostics.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

struct MeshVertex {
    float position[3];  ///< world space
    float normal[3];    ///< world space, unit length
    float uv[2];        ///< TEXCOORD_0 as the file has it (0, 0 without)
    /// World space, unit length and orthogonal to the normal; w (+1 or -1) is the bitangent's
    /// sign: bitangent = w * cross(normal, tangent). The file's TANGENT, else derived from the
    /// UVs, else any direction orthogonal to the normal.
    float tangent[4];
};

/// An image that materials sample: decoded to 8-bit RGBA, mip 0 only (the renderer makes the
/// rest of the chain).
struct MeshImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;  ///< width * height * 4 bytes, the first row first
    std::string name;           ///< "images[i]", for messages
};

/// How a texture repeats outside [0, 1] (glTF sampler wrapS / wrapT).
enum class MeshWrap : uint8_t { Repeat, ClampToEdge, MirroredRepeat };

/// A material's use of an image.
struct MeshTexture {
    int32_t image = -1;  ///< index into TriangleMesh::images; -1: none
    MeshWrap wrapS = MeshWrap::Repeat, wrapT = MeshWrap::Repeat;
    [[nodiscard]] bool present() const noexcept { return image >= 0; }
};

enum class MeshAlphaMode : uint8_t { Opaque, Mask, Blend };

/// A glTF metallic-roughness material: factors, and the textures that scale them. Base color
/// and emissive images hold sRGB values; the others linear ones (glTF 2.0 section 3.9).
struct MeshMaterial {
    std::array<double, 4> baseColor{1.0, 1.0, 1.0, 1.0};  ///< linear RGBA, each in [0, 1]
    double metallic = 1.0;                                ///< [0, 1]
    double roughness = 1.0;                               ///< [0, 1]
    std::array<double, 3> emissive{0.0, 0.0, 0.0};        ///< linear, >= 0
    MeshTexture baseColorTexture;                         ///< sRGB RGB, linear alpha
    MeshTexture metallicRoughnessTexture;                 ///< roughness in G, metallic in B
    MeshTexture normalTexture;                            ///< tangent space
    double normalScale = 1.0;
    MeshTexture occlusionTexture;                         ///< R
    double occlusionStrength = 1.0;                       ///< [0, 1]
    MeshTexture emissiveTexture;                          ///< sRGB
    /// Blend is drawn as Opaque: the forward pass has no sorted transparent pass.
    MeshAlphaMode alphaMode = MeshAlphaMode::Opaque;
    double alphaCutoff = 0.5;  ///< Mask: fragments with alpha below it are discarded
    bool doubleSided = false;
};

/// One draw: a run of `indices` with one material.
struct MeshPrimitive {
    uint32_t firstIndex = 0;
    uint32_t indexCount = 0;  ///< a multiple of 3
    MeshMaterial material;
    std::string name;  ///< "meshes[m].primitives[p]", for messages
};

/// A camera of the file, placed by its node.
struct MeshCamera {
    std::array<double, 3> position{0.0, 0.0, 0.0};
    std::array<double, 3> forward{0.0, 0.0, -1.0};  ///< unit
    std::array<double, 3> up{0.0, 1.0, 0.0};        ///< unit, orthogonal to forward
    double fovYDeg = 60.0;
    double near = 0.1;
};

/// Everything drawn from one file. A plain value; the scene shares it (shared_ptr), since
/// it can be large.
struct TriangleMesh {
    std::filesystem::path file;
    /// The files its buffers and images were read from, as the glTF names them (beside `file`).
    std::vector<std::filesystem::path> referencedFiles;
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;  ///< every index < vertices.size()
    std::vector<MeshPrimitive> primitives;
    std::vector<MeshImage> images;  ///< those that materials use; others are not decoded
    std::array<double, 3> boundsMin{0.0, 0.0, 0.0}, boundsMax{0.0, 0.0, 0.0};
    std::optional<MeshCamera> camera;  ///< the first camera of the default scene
};

/// Where a file's scene lands in the world: scaled, then rotated about X, then Y, then Z,
/// then translated. Angles in degrees.
struct MeshTransform {
    std::array<double, 3> translation{0.0, 0.0, 0.0};
    std::array<double, 3> rotationDeg{0.0, 0.0, 0.0};
    std::array<double, 3> scale{1.0, 1.0, 1.0};  ///< each > 0
};

/// What one file may bring, so that a bad count or a forged image header cannot exhaust
/// memory. A file past any limit is refused with a diagnostic before the memory is taken.
struct GltfLimits {
    size_t maxVertices = size_t(1) << 24;
    size_t maxIndices = size_t(3) << 24;
    size_t maxTextureSide = 16384;           ///< texels, either side of an image
    size_t maxImageBytes = size_t(1) << 30;  ///< decoded RGBA8 bytes of all the file's images
};

/// Reads the glTF file at `path` and flattens its default scene (or scene 0). Appends every
/// problem to `diagnostics`, each naming `path` and the JSON path in the file (an accessor,
/// node, primitive or material), and returns nullopt when there is any: nothing is drawn of a
/// file that is partly wrong. Refused: unreadable or malformed files, missing buffers, a file
/// without a scene or whose scene has no nodes, node cycles, accessors out of their buffers,
/// indices past the vertices, non-finite or zero-length data, primitives of points or lines,
/// sparse or normalized position data, required extensions, textures that sample texture
/// coordinates other than TEXCOORD_0, or that a primitive without TEXCOORD_0 uses, malformed
/// texture coordinates or tangents, images that are not PNG or JPEG (or a JPEG too short for
/// its size), sizes beyond `limits`.
[[nodiscard]] std::optional<TriangleMesh> loadGltf(const std::filesystem::path& path, const MeshTransform& transform,
                                                   Diagnostics& diagnostics, const GltfLimits& limits = {});

/// As loadGltf() for a file's bytes in memory (read during the call only): .glb when they
/// start with its magic, else .gltf text. `name` stands for the file in messages; buffers and
/// images with relative URIs are read from `baseDir`. Never throws for bad bytes.
[[nodiscard]] std::optional<TriangleMesh> loadGltfFromMemory(std::string_view bytes, const std::string& name,
                                                             const std::filesystem::path& baseDir,
                                                             const MeshTransform& transform, Diagnostics& diagnostics,
                                                             const GltfLimits& limits = {});

}  // namespace skygraph
