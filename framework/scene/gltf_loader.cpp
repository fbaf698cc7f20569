// loadGltf: tinygltf reads and parses the file; this file checks what tinygltf leaves to the
// caller (accessor bounds, index
// ranges, finite data, the node hierarchy) and flattens the default scene into world space.
#include <skygraph/triangle_mesh.hpp>

#include "gltf_json_types.hpp"

#include <stb/stb_image.h>
#include <tiny_gltf.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace skygraph {
namespace {

using glm::dmat3;
using glm::dmat4;
using glm::dvec3;

std::string at(const char* array, size_t i) { return std::string(array) + "[" + std::to_string(i) + "]"; }

bool finite(const dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

class GltfFlattener {
public:
    GltfFlattener(std::filesystem::path file, const tinygltf::Model& model, Diagnostics& diagnostics)
        : model_(model), diagnostics_(diagnostics) {
        mesh_.file = std::move(file);
    }

    std::optional<TriangleMesh> flatten(const dmat4& root) {
        for (const std::string& ext : model_.extensionsRequired)
            error("extensionsRequired", "the file requires extension '" + ext + "', which skygraph does not support");
        if (model_.scenes.empty()) {
            error("scenes", "the file has no scene: nothing to draw");
            return std::nullopt;
        }
        const size_t scene = model_.defaultScene >= 0 ? size_t(model_.defaultScene) : 0;
        if (scene >= model_.scenes.size()) {
            error("scene", "names scene " + std::to_string(scene) + " of " + std::to_string(model_.scenes.size()));
            return std::nullopt;
        }
        const std::string scenePath = at("scenes", scene) + ".nodes";
        if (model_.scenes[scene].nodes.empty()) error(scenePath, "the scene has no nodes: nothing to draw");
        onPath_.assign(model_.nodes.size(), false);
        for (size_t i = 0; i < model_.scenes[scene].nodes.size(); ++i)
            visit(model_.scenes[scene].nodes[i], root, scenePath + "[" + std::to_string(i) + "]");
        if (!failed_ && mesh_.indices.empty()) error(scenePath, "the scene draws no triangles");
        if (failed_) return std::nullopt;
        return std::move(mesh_);
    }

private:
    void error(const std::string& path, const std::string& message) {
        diagnostics_.add(Diagnostic{mesh_.file.string(), path, "", "", message});
        failed_ = true;
    }

    static dmat4 localMatrix(const tinygltf::Node& node) {
        if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());  // column-major, as glTF
        dmat4 m(1.0);
        if (node.translation.size() == 3) m = glm::translate(m, dvec3(node.translation[0], node.translation[1], node.translation[2]));
        if (node.rotation.size() == 4)  // glTF: x, y, z, w
            m *= glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
        if (node.scale.size() == 3) m = glm::scale(m, dvec3(node.scale[0], node.scale[1], node.scale[2]));
        return m;
    }

    void visit(int index, const dmat4& parent, const std::string& reference) {
        if (index < 0 || size_t(index) >= model_.nodes.size())
            return error(reference, "node " + std::to_string(index) + " does not exist (" +
                                        std::to_string(model_.nodes.size()) + " nodes)");
        const std::string path = at("nodes", size_t(index));
        if (onPath_[size_t(index)])
            return error(reference, "node " + std::to_string(index) + " is its own ancestor: the hierarchy has a cycle");
        const tinygltf::Node& node = model_.nodes[size_t(index)];
        const dmat4 world = parent * localMatrix(node);
        for (int c = 0; c < 4; ++c)
            if (!finite(dvec3(world[c])) || !std::isfinite(world[c][3]))
                return error(path, "its transform is not finite");
        onPath_[size_t(index)] = true;
        if (node.mesh >= 0) addMesh(size_t(node.mesh), world, path + ".mesh");
        if (node.camera >= 0 && !mesh_.camera) addCamera(size_t(node.camera), world, path + ".camera");
        for (size_t c = 0; c < node.children.size() && !failed_; ++c)
            visit(node.children[c], world, path + ".children[" + std::to_string(c) + "]");
        onPath_[size_t(index)] = false;
    }

    /// The bytes of `accessor`'s elements of `elementBytes` each, checked against its buffer
    /// view and buffer; empty (with an error) when they do not fit.
    struct Span {
        const unsigned char* data = nullptr;
        size_t stride = 0, count = 0;
    };
    Span elements(int index, size_t elementBytes, const std::string& what) {
        const std::string path = index >= 0 ? at("accessors", size_t(index)) : std::string("accessors");
        if (index < 0 || size_t(index) >= model_.accessors.size())
            return error(what, "accessor " + std::to_string(index) + " does not exist"), Span{};
        const tinygltf::Accessor& a = model_.accessors[size_t(index)];
        const std::string label = path + " (" + what + ")";
        if (a.sparse.isSparse) return error(label, "sparse accessors are not supported"), Span{};
        if (a.count == 0) return error(label, "has no elements"), Span{};
        if (a.bufferView < 0 || size_t(a.bufferView) >= model_.bufferViews.size())
            return error(label, "has no buffer view (" + std::to_string(a.bufferView) + ")"), Span{};
        const tinygltf::BufferView& view = model_.bufferViews[size_t(a.bufferView)];
        if (view.buffer < 0 || size_t(view.buffer) >= model_.buffers.size())
            return error(at("bufferViews", size_t(a.bufferView)), "names buffer " + std::to_string(view.buffer) + ", which does not exist"), Span{};
        const std::vector<unsigned char>& buffer = model_.buffers[size_t(view.buffer)].data;
        const size_t stride = view.byteStride ? view.byteStride : elementBytes;
        if (stride < elementBytes)
            return error(label, "byteStride " + std::to_string(stride) + " is less than an element's " + std::to_string(elementBytes) + " bytes"), Span{};
        if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
            return error(at("bufferViews", size_t(a.bufferView)), "bytes [" + std::to_string(view.byteOffset) + ", +" +
                                std::to_string(view.byteLength) + ") lie outside its buffer of " + std::to_string(buffer.size()) + " bytes"), Span{};
        const size_t needed = a.byteOffset + stride * (a.count - 1) + elementBytes;  // count <= 2^32: no overflow in size_t
        if (a.count > (size_t(1) << 32) || needed > view.byteLength)
            return error(label, std::to_string(a.count) + " elements need " + std::to_string(needed) +
                                    " bytes of its buffer view, which has " + std::to_string(view.byteLength)), Span{};
        return Span{buffer.data() + view.byteOffset + a.byteOffset, stride, a.count};
    }

    std::vector<dvec3> readVec3(int index, const std::string& what) {
        if (index >= 0 && size_t(index) < model_.accessors.size()) {
            const tinygltf::Accessor& a = model_.accessors[size_t(index)];
            if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || a.normalized) {
                error(at("accessors", size_t(index)) + " (" + what + ")", "must be VEC3 of FLOAT (5126)");
                return {};
            }
        }
        const Span s = elements(index, 12, what);
        std::vector<dvec3> out(s.count);
        for (size_t i = 0; i < s.count; ++i) {
            float f[3];
            std::memcpy(f, s.data + i * s.stride, sizeof f);
            out[i] = dvec3(f[0], f[1], f[2]);
            if (!finite(out[i])) {
                error(at("accessors", size_t(index)) + " (" + what + ")", "element " + std::to_string(i) + " is not finite");
                return {};
            }
        }
        return out;
    }

    std::vector<uint32_t> readIndices(int index, size_t vertexCount, const std::string& what) {
        const tinygltf::Accessor& a = model_.accessors[size_t(index)];
        const std::string label = at("accessors", size_t(index)) + " (" + what + ")";
        size_t bytes = 0;
        switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: bytes = 1; break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: bytes = 2; break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: bytes = 4; break;
            default: break;
        }
        if (a.type != TINYGLTF_TYPE_SCALAR || bytes == 0)
            return error(label, "indices must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT"), std::vector<uint32_t>{};
        const Span s = elements(index, bytes, what);
        std::vector<uint32_t> out(s.count);
        for (size_t i = 0; i < s.count; ++i) {
            uint32_t v = 0;
            std::memcpy(&v, s.data + i * s.stride, bytes);  // little-endian, as glTF
            if (v >= vertexCount) {
                error(label, "index " + std::to_string(i) + " is " + std::to_string(v) + ", past the primitive's " +
                                 std::to_string(vertexCount) + " vertices");
                return {};
            }
            out[i] = v;
        }
        return out;
    }

    MeshMaterial material(int index, const std::string& path, bool& hidden) {
        MeshMaterial m;
        if (index < 0) return m;  // glTF's default material
        if (size_t(index) >= model_.materials.size())
            return error(path, "material " + std::to_string(index) + " does not exist"), m;
        const tinygltf::Material& mat = model_.materials[size_t(index)];
        const std::string mpath = at("materials", size_t(index));
        const auto& pbr = mat.pbrMetallicRoughness;
        const auto unit = [&](double v, const std::string& key) {
            if (!(v >= 0.0 && v <= 1.0)) error(mpath + "." + key, "must be in [0, 1], got " + std::to_string(v));
            return std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 1.0);
        };
        if (pbr.baseColorFactor.size() == 4)
            for (int c = 0; c < 4; ++c)
                m.baseColor[size_t(c)] = unit(pbr.baseColorFactor[size_t(c)], "pbrMetallicRoughness.baseColorFactor[" + std::to_string(c) + "]");
        m.metallic = unit(pbr.metallicFactor, "pbrMetallicRoughness.metallicFactor");
        m.roughness = unit(pbr.roughnessFactor, "pbrMetallicRoughness.roughnessFactor");
        if (mat.emissiveFactor.size() == 3)
            for (int c = 0; c < 3; ++c) {
                const double e = mat.emissiveFactor[size_t(c)];
                if (!(e >= 0.0) || !std::isfinite(e)) error(mpath + ".emissiveFactor", "must be finite and >= 0");
                else m.emissive[size_t(c)] = e;
            }
        const auto texture = [&](int t, const std::string& key) {
            if (t >= 0 && size_t(t) >= model_.textures.size())
                error(mpath + "." + key + ".index", "texture " + std::to_string(t) + " does not exist");
        };
        texture(pbr.baseColorTexture.index, "pbrMetallicRoughness.baseColorTexture");
        texture(pbr.metallicRoughnessTexture.index, "pbrMetallicRoughness.metallicRoughnessTexture");
        texture(mat.normalTexture.index, "normalTexture");
        texture(mat.occlusionTexture.index, "occlusionTexture");
        texture(mat.emissiveTexture.index, "emissiveTexture");
        // MASK: a primitive whose alpha is below the cutoff everywhere draws nothing.
        hidden = mat.alphaMode == "MASK" && m.baseColor[3] < mat.alphaCutoff;
        return m;
    }

    /// A strip's or fan's triangles as a list, each wound as the first one (glTF 2.0,
    /// "Primitive"); fewer than three indices make none.
    static std::vector<uint32_t> triangleList(const std::vector<uint32_t>& in, bool strip) {
        std::vector<uint32_t> out;
        for (size_t i = 0; i + 2 < in.size(); ++i) {
            if (strip) out.insert(out.end(), {in[i + (i % 2)], in[i + 1 - (i % 2)], in[i + 2]});
            else out.insert(out.end(), {in[i + 1], in[i + 2], in[0]});
        }
        return out;
    }

    void addMesh(size_t meshIndex, const dmat4& world, const std::string& reference) {
        if (meshIndex >= model_.meshes.size())
            return error(reference, "mesh " + std::to_string(meshIndex) + " does not exist");
        const dmat3 linear(world);
        const dmat3 normalMatrix = glm::transpose(glm::inverse(linear));
        const bool mirrored = glm::determinant(linear) < 0.0;
        const tinygltf::Mesh& mesh = model_.meshes[meshIndex];
        for (size_t p = 0; p < mesh.primitives.size() && !failed_; ++p) {
            const tinygltf::Primitive& prim = mesh.primitives[p];
            const std::string path = at("meshes", meshIndex) + ".primitives[" + std::to_string(p) + "]";
            const int mode = prim.mode == -1 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
                return error(path + ".mode", "mode " + std::to_string(prim.mode) +
                                                 " draws points or lines; expected triangles (4), a strip (5) or a fan (6)");
            const auto position = prim.attributes.find("POSITION");
            if (position == prim.attributes.end()) return error(path + ".attributes", "has no POSITION");
            std::vector<dvec3> positions = readVec3(position->second, "POSITION of " + path);
            if (failed_) return;
            std::vector<dvec3> normals;
            if (const auto n = prim.attributes.find("NORMAL"); n != prim.attributes.end()) {
                normals = readVec3(n->second, "NORMAL of " + path);
                if (failed_) return;
                if (normals.size() != positions.size())
                    return error(at("accessors", size_t(n->second)) + " (NORMAL of " + path + ")",
                                 std::to_string(normals.size()) + " normals for " + std::to_string(positions.size()) + " positions");
                for (size_t i = 0; i < normals.size(); ++i)
                    if (!(glm::length(normals[i]) > 1e-6))
                        return error(at("accessors", size_t(n->second)) + " (NORMAL of " + path + ")",
                                     "normal " + std::to_string(i) + " has length " + std::to_string(glm::length(normals[i])) +
                                         "; normals must be unit vectors");
            }
            std::vector<uint32_t> indices;
            if (prim.indices >= 0) {
                if (size_t(prim.indices) >= model_.accessors.size())
                    return error(path + ".indices", "accessor " + std::to_string(prim.indices) + " does not exist");
                indices = readIndices(prim.indices, positions.size(), "indices of " + path);
                if (failed_) return;
            } else {
                indices.resize(positions.size());
                for (size_t i = 0; i < indices.size(); ++i) indices[i] = uint32_t(i);
            }
            if (mode != TINYGLTF_MODE_TRIANGLES) indices = triangleList(indices, mode == TINYGLTF_MODE_TRIANGLE_STRIP);
            if (indices.size() % 3 != 0)
                return error(path, std::to_string(indices.size()) + " indices do not make whole triangles");
            bool hidden = false;
            MeshPrimitive out;
            out.material = material(prim.material, path + ".material", hidden);
            out.name = path;
            if (failed_ || hidden) continue;
            const size_t newVertices = normals.empty() ? indices.size() : positions.size();
            if (mesh_.vertices.size() + newVertices > kMaxMeshVertices || mesh_.indices.size() + indices.size() > kMaxMeshIndices)
                return error(path, "the file has more than " + std::to_string(kMaxMeshVertices) + " vertices or " +
                                       std::to_string(kMaxMeshIndices) + " indices");
            const auto base = uint32_t(mesh_.vertices.size());
            const auto place = [&](const dvec3& local, const dvec3& localNormal) {
                const dvec3 wp = dvec3(world * glm::dvec4(local, 1.0));
                const dvec3 wn = glm::normalize(normalMatrix * localNormal);
                MeshVertex v{{float(wp.x), float(wp.y), float(wp.z)}, {float(wn.x), float(wn.y), float(wn.z)}};
                if (mesh_.vertices.empty() && mesh_.indices.empty()) mesh_.boundsMin = mesh_.boundsMax = {wp.x, wp.y, wp.z};
                for (int c = 0; c < 3; ++c) {
                    mesh_.boundsMin[size_t(c)] = std::min(mesh_.boundsMin[size_t(c)], wp[c]);
                    mesh_.boundsMax[size_t(c)] = std::max(mesh_.boundsMax[size_t(c)], wp[c]);
                }
                mesh_.vertices.push_back(v);
            };
            out.firstIndex = uint32_t(mesh_.indices.size());
            if (normals.empty()) {
                // No normals: flat shading (glTF 2.0, "Meshes"), one vertex per corner.
                for (size_t t = 0; t < indices.size(); t += 3) {
                    const dvec3 a = positions[indices[t]], b = positions[indices[t + 1]], c = positions[indices[t + 2]];
                    const dvec3 cross = glm::cross(b - a, c - a);
                    const dvec3 n = glm::length(cross) > 0.0 ? glm::normalize(cross) : dvec3(0.0, 1.0, 0.0);
                    for (const dvec3& corner : {a, b, c}) place(corner, n);
                    for (uint32_t k = 0; k < 3; ++k) mesh_.indices.push_back(base + uint32_t(t) + (mirrored ? 2 - k : k));
                }
            } else {
                for (size_t i = 0; i < positions.size(); ++i) place(positions[i], normals[i]);
                for (size_t t = 0; t < indices.size(); t += 3)
                    for (uint32_t k = 0; k < 3; ++k) mesh_.indices.push_back(base + indices[t + (mirrored ? 2 - k : k)]);
            }
            out.indexCount = uint32_t(indices.size());
            mesh_.primitives.push_back(std::move(out));
        }
    }

    void addCamera(size_t index, const dmat4& world, const std::string& reference) {
        if (index >= model_.cameras.size()) return error(reference, "camera " + std::to_string(index) + " does not exist");
        const tinygltf::Camera& c = model_.cameras[index];
        const std::string path = at("cameras", index);
        if (c.type != "perspective") return;  // only a perspective camera can be the scene's
        if (!(c.perspective.yfov > 0.0 && c.perspective.yfov < M_PI))
            return error(path + ".perspective.yfov", "must be in (0, pi) radians");
        if (!(c.perspective.znear > 0.0 && std::isfinite(c.perspective.znear)))
            return error(path + ".perspective.znear", "must be > 0");
        const dmat3 linear(world);
        const dvec3 forward = linear * dvec3(0.0, 0.0, -1.0), up = linear * dvec3(0.0, 1.0, 0.0);
        if (!(glm::length(forward) > 1e-12) || !(glm::length(glm::cross(forward, up)) > 1e-12))
            return error(reference, "the camera's node transform is degenerate");
        const dvec3 f = glm::normalize(forward);
        const dvec3 u = glm::normalize(up - f * glm::dot(up, f));
        MeshCamera cam;
        cam.position = {world[3].x, world[3].y, world[3].z};
        cam.forward = {f.x, f.y, f.z};
        cam.up = {u.x, u.y, u.z};
        cam.fovYDeg = glm::degrees(c.perspective.yfov);
        cam.near = c.perspective.znear;
        mesh_.camera = cam;
    }

    const tinygltf::Model& model_;
    Diagnostics& diagnostics_;
    TriangleMesh mesh_;
    std::vector<bool> onPath_;
    bool failed_ = false;
};

/// tinygltf's image callback: the textures are not sampled yet, so an image is only checked
/// (stb reads its header: a known format, a sane size) and never decoded, which keeps a large
/// or hostile image from costing time and memory.
bool checkImageHeader(tinygltf::Image* image, const int index, std::string* error, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
    int width = 0, height = 0, components = 0;
    const std::string where = "images[" + std::to_string(index) + "]";
    if (!stbi_info_from_memory(bytes, size, &width, &height, &components)) {
        *error += where + ": not an image stb can read (" + std::string(stbi_failure_reason()) + ")\n";
        return false;
    }
    if (width > int(kMaxMeshTextureSide) || height > int(kMaxMeshTextureSide)) {
        *error += where + ": " + std::to_string(width) + "x" + std::to_string(height) + " is larger than " +
                  std::to_string(kMaxMeshTextureSide) + " texels a side\n";
        return false;
    }
    image->width = width;
    image->height = height;
    image->component = components;
    return true;
}

dmat4 transformMatrix(const MeshTransform& t) {
    dmat4 m = glm::translate(dmat4(1.0), dvec3(t.translation[0], t.translation[1], t.translation[2]));
    m = glm::rotate(m, glm::radians(t.rotationDeg[2]), dvec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(t.rotationDeg[1]), dvec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(t.rotationDeg[0]), dvec3(1, 0, 0));
    return glm::scale(m, dvec3(t.scale[0], t.scale[1], t.scale[2]));
}

}  // namespace

std::optional<TriangleMesh> loadGltfFromMemory(std::string_view bytes, const std::string& name,
                                               const std::filesystem::path& baseDir, const MeshTransform& transform,
                                               Diagnostics& diagnostics) {
    const auto fail = [&](const std::string& message) {
        diagnostics.add(Diagnostic{name, "", "", "", message});
        return std::nullopt;
    };
    if (bytes.size() > std::numeric_limits<unsigned>::max()) return fail("is larger than 4 GiB");
    const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    if (const auto text = binary ? glbJsonChunk(bytes) : std::optional<std::string>(std::string(bytes));
        text && !checkGltfJsonTypes(*text, name, diagnostics))
        return std::nullopt;
    tinygltf::TinyGLTF reader;
    reader.SetImageLoader(checkImageHeader, nullptr);
    tinygltf::Model model;
    std::string error, warning;
    bool read = false;
    try {
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        read = binary ? reader.LoadBinaryFromMemory(&model, &error, &warning, data, unsigned(bytes.size()), baseDir.string())
                      : reader.LoadASCIIFromString(&model, &error, &warning, bytes.data(), unsigned(bytes.size()),
                                                   baseDir.string());
    } catch (const std::exception& e) {
        return fail(std::string("glTF: ") + e.what());
    }
    if (!read || !error.empty()) {
        std::istringstream lines(error.empty() ? std::string("tinygltf could not read it") : error);
        const size_t before = diagnostics.size();
        for (std::string line; std::getline(lines, line);)
            if (!line.empty()) diagnostics.add(Diagnostic{name, "", "", "", "glTF: " + line});
        if (diagnostics.size() == before) fail("glTF: tinygltf could not read it");
        return std::nullopt;
    }
    return GltfFlattener(name, model, diagnostics).flatten(transformMatrix(transform));
}

std::optional<TriangleMesh> loadGltf(const std::filesystem::path& path, const MeshTransform& transform,
                                     Diagnostics& diagnostics) {
    const auto fail = [&](const std::string& message) {
        diagnostics.add(Diagnostic{path.string(), "", "", "", message});
        return std::nullopt;
    };
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return fail("does not exist or is not a file");
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (extension != ".gltf" && extension != ".glb") return fail("is neither a .gltf nor a .glb file");
    std::ifstream in(path, std::ios::binary);
    std::ostringstream bytes;
    if (!(bytes << in.rdbuf())) return fail("cannot be read");
    std::optional<TriangleMesh> mesh = loadGltfFromMemory(bytes.str(), path.string(),
                                                          std::filesystem::absolute(path, ec).parent_path(), transform, diagnostics);
    if (mesh) mesh->file = std::filesystem::absolute(path, ec);
    return mesh;
}

}  // namespace skygraph
