// The fuzz target over the glTF loader (tinygltf and the checks around it): any bytes must
// end in a mesh whose indices and primitives are in range, or in diagnostics. Relative URIs
// resolve in a folder that does not exist, so an input reads no file of the machine's.
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

void checkMesh(const TriangleMesh& mesh) {
    if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) broken("a mesh without whole triangles");
    for (uint32_t i : mesh.indices)
        if (i >= mesh.vertices.size()) broken("an index past the vertices");
    for (const MeshPrimitive& p : mesh.primitives)
        if (size_t(p.firstIndex) + p.indexCount > mesh.indices.size()) broken("a primitive past the indices");
    for (const MeshVertex& v : mesh.vertices)
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(v.position[c]) || !std::isfinite(v.normal[c])) broken("a non-finite vertex");
}

}  // namespace

void runOneGltfInput(std::string_view bytes) {
    try {
        Diagnostics diagnostics;
        const auto mesh = loadGltfFromMemory(bytes, "<fuzz>", "/nonexistent-skygraph-fuzz", {}, diagnostics);
        if (mesh) checkMesh(*mesh);
        else if (diagnostics.empty()) broken("no mesh and no diagnostic");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glTF fuzz target: %s escaped\n", e.what());
        std::abort();
    }
}

}  // namespace skygraph::fuzz
