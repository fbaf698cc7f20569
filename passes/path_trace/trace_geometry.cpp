#include "trace_geometry.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

namespace skygraph::passes {
namespace {

class Flattener {
public:
    explicit Flattener(TraceGeometry& g) : g_(g) {}

    void add(uint32_t modelIndex, const TriangleMesh& mesh) {
        const auto firstVertex = uint32_t(g_.vertices.size());
        for (const MeshVertex& v : mesh.vertices)
            g_.vertices.push_back({{v.position[0], v.position[1], v.position[2], v.uv[0]},
                                   {v.normal[0], v.normal[1], v.normal[2], v.uv[1]},
                                   {v.tangent[0], v.tangent[1], v.tangent[2], v.tangent[3]}});
        for (const MeshPrimitive& p : mesh.primitives) {
            const auto material = uint32_t(g_.materials.size());
            g_.materials.push_back(materialOf(modelIndex, mesh, p.material));
            for (uint32_t i = p.firstIndex; i + 2 < p.firstIndex + p.indexCount; i += 3) {
                std::array<uint32_t, 3> v{};
                TriangleCorners corners{};
                for (int k = 0; k < 3; ++k) {
                    v[size_t(k)] = firstVertex + mesh.indices[i + uint32_t(k)];
                    const float* pos = mesh.vertices[mesh.indices[i + uint32_t(k)]].position;
                    corners[size_t(k)] = {pos[0], pos[1], pos[2]};
                }
                triangles_.push_back({v[0], v[1], v[2], material});
                corners_.push_back(corners);
            }
        }
    }

    void finish() {
        const TriangleBvh bvh = buildTriangleBvh(corners_);
        g_.nodes = bvh.nodes;
        g_.bvhDepth = bvh.depth;
        g_.triangles.reserve(bvh.triangles.size() * 4);
        for (uint32_t t : bvh.triangles) g_.triangles.insert(g_.triangles.end(), triangles_[t].begin(), triangles_[t].end());
    }

private:
    /// The table entry of `t` read as sRGB or linear, added on first use; its image's texels
    /// go in once however many entries read them.
    int32_t slotOf(uint32_t model, const TriangleMesh& mesh, const MeshTexture& t, bool srgb) {
        if (!t.present()) return -1;
        const MeshImage& image = mesh.images.at(size_t(t.image));
        const std::pair<uint32_t, int32_t> imageKey{model, t.image};
        auto [at, fresh] = firstTexel_.try_emplace(imageKey, uint32_t(g_.texels.size()));
        if (fresh) {
            if (g_.texels.size() + image.rgba.size() / 4 > std::numeric_limits<uint32_t>::max())
                throw std::length_error(mesh.file.string() + ": the scene's textures pass 2^32 texels");
            const size_t first = g_.texels.size();
            g_.texels.resize(first + image.rgba.size() / 4);
            std::memcpy(g_.texels.data() + first, image.rgba.data(), image.rgba.size());
        }
        const TraceTextureEntry entry{at->second, image.width, image.height,
                                      uint32_t(t.wrapS) | uint32_t(t.wrapT) << 2 | (srgb ? 16u : 0u)};
        for (size_t i = 0; i < g_.textures.size(); ++i) {
            const TraceTextureEntry& e = g_.textures[i];
            if (e.firstTexel == entry.firstTexel && e.flags == entry.flags) return int32_t(i);
        }
        g_.textures.push_back(entry);
        return int32_t(g_.textures.size() - 1);
    }

    TraceMaterial materialOf(uint32_t model, const TriangleMesh& mesh, const MeshMaterial& m) {
        TraceMaterial t{};
        for (int i = 0; i < 4; ++i) t.baseColor[i] = float(m.baseColor[size_t(i)]);
        for (int i = 0; i < 3; ++i) t.emissiveRoughness[i] = float(m.emissive[size_t(i)]);
        t.emissiveRoughness[3] = float(m.roughness);
        t.metallicNormalScaleAlpha[0] = float(m.metallic);
        t.metallicNormalScaleAlpha[1] = m.normalTexture.present() ? float(m.normalScale) : 0.0f;
        // Mask: a texel is kept where its alpha times the factor's reaches the cutoff.
        t.metallicNormalScaleAlpha[2] = m.alphaMode != MeshAlphaMode::Mask ? -1.0f
                                        : m.baseColor[3] > 0.0          ? float(m.alphaCutoff / m.baseColor[3])
                                                                         : 2.0f;
        t.textures[0] = slotOf(model, mesh, m.baseColorTexture, true);
        t.textures[1] = slotOf(model, mesh, m.metallicRoughnessTexture, false);
        t.textures[2] = slotOf(model, mesh, m.normalTexture, false);
        t.textures[3] = slotOf(model, mesh, m.emissiveTexture, true);
        return t;
    }

    TraceGeometry& g_;
    std::vector<std::array<uint32_t, 4>> triangles_;
    std::vector<TriangleCorners> corners_;
    std::map<std::pair<uint32_t, int32_t>, uint32_t> firstTexel_;  ///< (model, image) -> its first texel
};

}  // namespace

TraceGeometry buildTraceGeometry(std::vector<std::shared_ptr<const TriangleMesh>> models) {
    TraceGeometry g;
    g.models = std::move(models);
    Flattener f(g);
    for (uint32_t m = 0; m < g.models.size(); ++m) f.add(m, *g.models[m]);
    f.finish();
    return g;
}

}  // namespace skygraph::passes
