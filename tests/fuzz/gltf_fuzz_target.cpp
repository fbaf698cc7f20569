// The fuzz target over the glTF loader (tinygltf and the checks around it): any bytes must
// end in a mesh whose indices, primitives and textures are in range, whose vertices are finite
// with unit tangents orthogonal to their normals, and whose images hold the bytes their sizes
// say; or in diagnostics. Relative URIs resolve in a folder that does not exist, so an input
// reads no file of the machine's.
#include "gltf_fuzz_target.hpp"

#include <skygraph/triangle_mesh.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

namespace skygraph::fuzz {
namespace {

[[noreturn]] void broken(const char* what) {
    std::fprintf(stderr, "glTF fuzz target: %s\n", what);
    std::abort();
}

/// Smaller than the loader's defaults, so that what an input may take stays well inside
/// libFuzzer's malloc limit (tools/fuzz.sh) while the limits themselves are still reached.
GltfLimits fuzzLimits() {
    GltfLimits limits;
    limits.maxVertices = size_t(1) << 20;
    limits.maxIndices = size_t(3) << 20;
    limits.maxTextureSide = 4096;
    limits.maxImageBytes = size_t(32) << 20;
    return limits;
}

void checkMesh(const TriangleMesh& mesh, const GltfLimits& limits) {
    if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) broken("a mesh without whole triangles");
    if (mesh.vertices.size() > limits.maxVertices || mesh.indices.size() > limits.maxIndices)
        broken("vertices or indices past the limits");
    for (uint32_t i : mesh.indices)
        if (i >= mesh.vertices.size()) broken("an index past the vertices");
    for (const MeshPrimitive& p : mesh.primitives)
        if (size_t(p.firstIndex) + p.indexCount > mesh.indices.size()) broken("a primitive past the indices");
    for (const MeshVertex& v : mesh.vertices) {
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(v.position[c]) || !std::isfinite(v.normal[c])) broken("a non-finite vertex");
        if (!std::isfinite(v.uv[0]) || !std::isfinite(v.uv[1])) broken("a non-finite texture coordinate");
        const double tx = v.tangent[0], ty = v.tangent[1], tz = v.tangent[2];
        if (!std::isfinite(tx) || !std::isfinite(ty) || !std::isfinite(tz)) broken("a non-finite tangent");
        if (std::abs(std::sqrt(tx * tx + ty * ty + tz * tz) - 1.0) > 1e-4) broken("a tangent that is not unit");
        if (std::abs(tx * v.normal[0] + ty * v.normal[1] + tz * v.normal[2]) > 1e-3)
            broken("a tangent not orthogonal to its normal");
        if (v.tangent[3] != 1.0f && v.tangent[3] != -1.0f) broken("a bitangent sign that is not +1 or -1");
    }
    size_t imageBytes = 0;
    for (const MeshImage& image : mesh.images) {
        if (image.width == 0 || image.height == 0 || image.width > limits.maxTextureSide ||
            image.height > limits.maxTextureSide || image.rgba.size() != size_t(image.width) * image.height * 4)
            broken("an image whose size and bytes disagree");
        imageBytes += image.rgba.size();
    }
    if (imageBytes > limits.maxImageBytes) broken("images past maxImageBytes");
    for (const MeshPrimitive& p : mesh.primitives) {
        const MeshMaterial& m = p.material;
        for (const MeshTexture* t : {&m.baseColorTexture, &m.metallicRoughnessTexture, &m.normalTexture,
                                     &m.occlusionTexture, &m.emissiveTexture})
            if (t->image < -1 || t->image >= int64_t(mesh.images.size())) broken("a texture past the images");
    }
}

}  // namespace

void runOneGltfInput(std::string_view bytes) {
    try {
        Diagnostics diagnostics;
        const GltfLimits limits = fuzzLimits();
        const auto mesh = loadGltfFromMemory(bytes, "<fuzz>", "/nonexistent-skygraph-fuzz", {}, diagnostics, limits);
        if (mesh) checkMesh(*mesh, limits);
        else if (diagnostics.empty()) broken("no mesh and no diagnostic");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glTF fuzz target: %s escaped\n", e.what());
        std::abort();
    }
}

}  // namespace skygraph::fuzz
