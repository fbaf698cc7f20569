// loadGltf: tinygltf reads and parses the file; this file checks what tinygltf leaves to the
// caller (accessor bounds, index ranges, finite data, the node hierarchy) and flattens the
// default scene into world space, tangents included, so that nothing is left to compute per
// frame. Materials and their images: gltf_materials.cpp.
#include <skygraph/triangle_mesh.hpp>

#include "file_extension.hpp"
#include "gltf_json_types.hpp"
#include "gltf_materials.hpp"

#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <system_error>
#include <utility>

namespace skygraph {
namespace {

using glm::dmat3;
using glm::dmat4;
using glm::dvec3;

std::string at(const char* array, size_t i) { return std::string(array) + "[" + std::to_string(i) + "]"; }

bool finite(const dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }


/// What tinygltf's file callbacks share: the glTF's folder, the paths read so far, and the
/// file each uri with a '+' names, under the name tinygltf asks for (with a space there).
struct ExternalFiles {
    std::string baseDir;  ///< As tinygltf joins it to a uri.
    std::vector<std::filesystem::path> read;
    std::vector<std::pair<std::string, std::string>> plusUris;  ///< (as tinygltf decodes it, as it should)

    /// The file `path` (as tinygltf joined it) names.
    [[nodiscard]] std::string actual(const std::string& path) const {
        for (const auto& [asked, meant] : plusUris)
            if (path.size() >= asked.size() && path.compare(path.size() - asked.size(), asked.size(), asked) == 0 &&
                (path.size() == asked.size() || path[path.size() - asked.size() - 1] == '/'))
                return path.substr(0, path.size() - asked.size()) + meant;
        return path;
    }
};

/// Every buffer and image uri of the glTF JSON `json` that holds a '+' (not a data URI).
std::vector<std::pair<std::string, std::string>> urisWithPlus(const std::string& json) {
    std::vector<std::pair<std::string, std::string>> found;
    if (json.find('+') == std::string::npos) return found;
    const nlohmann::json doc = nlohmann::json::parse(json, nullptr, false);
    if (!doc.is_object()) return found;  // checkGltfJsonTypes has said why
    for (const char* array : {"buffers", "images"}) {
        const auto list = doc.find(array);
        if (list == doc.end() || !list->is_array()) continue;
        for (const nlohmann::json& item : *list) {
            if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
            const std::string uri = item["uri"].get<std::string>();
            if (uri.find('+') != std::string::npos && !uri.starts_with("data:"))
                found.emplace_back(decodeUri(uri, true), decodeUri(uri, false));
        }
    }
    return found;
}

/// tinygltf's file callbacks, for a buffer's or an image's uri: only regular files are read.
/// Its own would block forever on a FIFO and read a directory's size as bytes to allocate.
/// Anything that exists is found, so that readRegularFile says what it is rather than tinygltf
/// saying "File not found". tinygltf looks for a uri in the working directory too, after the
/// glTF's folder: a file found there is not the model's, so only paths in that folder exist.
bool fileExists(const std::string& asked, void* data) {
    const auto* files = static_cast<const ExternalFiles*>(data);
    const std::string path = files->actual(asked);
    const std::string& base = files->baseDir;
    if (!base.empty() && (path.compare(0, base.size(), base) != 0 ||
                          (base.back() != '/' && path.size() > base.size() && path[base.size()] != '/')))
        return false;
    std::error_code ec;
    return std::filesystem::exists(path, ec);
}

bool readRegularFile(std::vector<unsigned char>* out, std::string* error, const std::string& asked, void* data) {
    auto* files = static_cast<ExternalFiles*>(data);
    const std::string path = files->actual(asked);
    files->read.emplace_back(path);
    if (const std::string why = notARegularFile(path); !why.empty()) {
        if (error) *error += "'" + path + "' " + why + "\n";
        return false;
    }
    std::ifstream in(path, std::ios::binary);
    out->assign(std::istreambuf_iterator<char>(in), {});
    if (in.bad()) {
        if (error) *error += "'" + path + "' cannot be read\n";
        return false;
    }
    return true;
}

/// By image index: whether only a texture's extension names the image (`"extensions":
/// {"KHR_texture_basisu": {"source": 1}}`) and no texture's own `source` does. skygraph reads
/// no texture extension, and a file that requires one is refused before this, so such an image
/// is for readers that have the extension and need not be in a format stb reads (KTX2, WebP):
/// a reader without the extension samples the texture's own `source`, its fallback (glTF 2.0).
std::vector<bool> imagesOnlyExtensionsName(const tinygltf::Model& model) {
    std::vector<bool> byExtension(model.images.size(), false), bySource(model.images.size(), false);
    const auto mark = [&](std::vector<bool>& named, int image) {
        if (image >= 0 && size_t(image) < named.size()) named[size_t(image)] = true;
    };
    for (const tinygltf::Texture& texture : model.textures) {
        mark(bySource, texture.source);
        for (const auto& [name, extension] : texture.extensions)
            if (extension.IsObject() && extension.Has("source") && extension.Get("source").IsInt())
                mark(byExtension, extension.Get("source").GetNumberAsInt());
    }
    std::vector<bool> only(model.images.size());
    for (size_t i = 0; i < only.size(); ++i) only[i] = byExtension[i] && !bySource[i];
    return only;
}

/// A vertex attribute as skygraph reads it: its accessor type and, for texture coordinates,
/// the normalized integers glTF allows besides floats.
struct AttributeFormat {
    const char* name;
    int type;
    size_t components;
    bool normalizedIntegers;
    const char* expected;
    const char* noun;  ///< one element, for messages
};
constexpr AttributeFormat kPosition{"POSITION", TINYGLTF_TYPE_VEC3, 3, false, "VEC3 of FLOAT (5126)", "position"};
constexpr AttributeFormat kNormal{"NORMAL", TINYGLTF_TYPE_VEC3, 3, false, "VEC3 of FLOAT (5126)", "normal"};
constexpr AttributeFormat kTexCoord{
    "TEXCOORD_0", TINYGLTF_TYPE_VEC2, 2, true,
    "VEC2 of FLOAT (5126), or of normalized UNSIGNED_BYTE (5121) or UNSIGNED_SHORT (5123)", "texture coordinate"};
constexpr AttributeFormat kTangent{"TANGENT", TINYGLTF_TYPE_VEC4, 4, false, "VEC4 of FLOAT (5126)", "tangent"};

std::vector<dvec3> vec3s(const std::vector<double>& values, size_t stride) {
    std::vector<dvec3> out(values.size() / stride);
    for (size_t i = 0; i < out.size(); ++i)
        out[i] = dvec3(values[i * stride], values[i * stride + 1], values[i * stride + 2]);
    return out;
}

/// What carries normals to world space: the inverse transpose of `linear`; for a transform
/// without an inverse (a node scaled to 0 on an axis flattens its mesh), the cofactor matrix,
/// which is the inverse transpose times the determinant where both exist.
dmat3 normalMatrixOf(const dmat3& linear) {
    const dmat3 inverseTranspose = glm::transpose(glm::inverse(linear));
    bool invertible = true;
    for (int c = 0; c < 3; ++c) invertible = invertible && finite(inverseTranspose[c]);
    if (invertible) return inverseTranspose;
    return dmat3(glm::cross(linear[1], linear[2]), glm::cross(linear[2], linear[0]), glm::cross(linear[0], linear[1]));
}

/// A unit vector orthogonal to unit `n`, for a tangent that nothing else defines.
dvec3 orthogonalTo(const dvec3& n) {
    const dvec3 axis = std::abs(n.x) < 0.9 ? dvec3(1.0, 0.0, 0.0) : dvec3(0.0, 1.0, 0.0);
    return glm::normalize(axis - n * glm::dot(n, axis));
}

/// `t` made orthogonal to unit `n` and unit (Gram-Schmidt); any orthogonal direction where `t`
/// is (nearly) parallel to `n`, zero or not finite.
dvec3 tangentTo(const dvec3& n, const dvec3& t) {
    const double largest = std::max({std::abs(t.x), std::abs(t.y), std::abs(t.z)});
    if (!(largest > 0.0 && std::isfinite(largest))) return orthogonalTo(n);
    const dvec3 scaled = t / largest;  // length in [1, 2]: no overflow below
    const dvec3 orthogonal = scaled - n * glm::dot(n, scaled);
    const double length = glm::length(orthogonal);
    return length > 1e-6 ? orthogonal / length : orthogonalTo(n);
}

void setTangent(MeshVertex& v, const dvec3& t, double w) {
    v.tangent[0] = float(t.x);
    v.tangent[1] = float(t.y);
    v.tangent[2] = float(t.z);
    v.tangent[3] = w < 0.0 ? -1.0f : 1.0f;
}

class GltfFlattener {
public:
    GltfFlattener(std::filesystem::path file, const tinygltf::Model& model, const std::filesystem::path& baseDir,
                  const GltfLimits& limits, Diagnostics& diagnostics)
        : model_(model), limits_(limits), diagnostics_(diagnostics),
          materials_(model, baseDir, limits.maxImageBytes,
                     [this](const std::string& path, const std::string& message) { error(path, message); }) {
        mesh_.file = std::move(file);
    }

    std::optional<TriangleMesh> flatten(const dmat4& root) {
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
        visited_.assign(model_.nodes.size(), false);
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
        if (node.rotation.size() == 4)  // glTF: x, y, z, w; within the unit length enter() allows
            m *= glm::mat4_cast(
                glm::normalize(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2])));
        if (node.scale.size() == 3) m = glm::scale(m, dvec3(node.scale[0], node.scale[1], node.scale[2]));
        return m;
    }

    /// The tree under scene node `index`, depth first. With a stack of its own: a chain of
    /// nodes as deep as a file likes would overflow the thread's stack if visited recursively.
    /// Each node is visited once, so a node shared by two parents (glTF's nodes form disjoint
    /// trees) is an error rather than a mesh drawn twice or a hierarchy that doubles per level.
    void visit(int index, const dmat4& root, const std::string& reference) {
        struct Frame {
            size_t node;
            dmat4 world;
            std::string path;
            size_t nextChild = 0;
        };
        std::vector<Frame> stack;
        const auto enter = [&](int i, const dmat4& parent, const std::string& ref) {
            if (i < 0 || size_t(i) >= model_.nodes.size())
                return error(ref, "node " + std::to_string(i) + " does not exist (" +
                                      std::to_string(model_.nodes.size()) + " nodes)");
            const size_t n = size_t(i);
            if (onPath_[n]) return error(ref, "node " + std::to_string(i) + " is its own ancestor: the hierarchy has a cycle");
            if (visited_[n])
                return error(ref, "node " + std::to_string(i) +
                                      " is reached twice (a child of two nodes, or a scene root twice): glTF nodes "
                                      "form disjoint trees");
            const std::string path = at("nodes", n);
            const tinygltf::Node& node = model_.nodes[n];
            // glTF's rotation is a unit quaternion and its matrix an affine transform: another
            // quaternion (a zero one was drawn as no rotation) or a projective last row was drawn
            // as something else without a word. Exporters quantize: glTF-Validator allows a
            // length within 0.00769 of 1 (8-bit components), which localMatrix normalizes.
            if (node.rotation.size() == 4) {
                const double length =
                    glm::length(glm::dvec4(node.rotation[0], node.rotation[1], node.rotation[2], node.rotation[3]));
                if (!(std::abs(length - 1.0) <= 0.00769))
                    return error(path + ".rotation",
                                 "must be a unit quaternion, but its length is " + std::to_string(length));
            }
            if (node.matrix.size() == 16 &&
                !(node.matrix[3] == 0.0 && node.matrix[7] == 0.0 && node.matrix[11] == 0.0 && node.matrix[15] == 1.0))
                return error(path + ".matrix", "is not an affine transform: its last row must be 0, 0, 0, 1");
            const dmat4 world = parent * localMatrix(node);
            for (int c = 0; c < 4; ++c)
                if (!finite(dvec3(world[c])) || !std::isfinite(world[c][3])) return error(path, "its transform is not finite");
            onPath_[n] = visited_[n] = true;
            if (node.mesh >= 0) addMesh(size_t(node.mesh), world, path + ".mesh");
            if (node.camera >= 0 && !mesh_.camera) addCamera(size_t(node.camera), world, path + ".camera");
            stack.push_back({n, world, path});
        };
        enter(index, root, reference);
        while (!stack.empty() && !failed_) {
            Frame& top = stack.back();
            const std::vector<int>& children = model_.nodes[top.node].children;
            if (top.nextChild == children.size()) {
                onPath_[top.node] = false;
                stack.pop_back();
                continue;
            }
            const size_t c = top.nextChild++;
            const dmat4 world = top.world;  // enter() may move the stack's frames
            enter(children[c], world, top.path + ".children[" + std::to_string(c) + "]");
        }
        for (const Frame& left : stack) onPath_[left.node] = false;  // after an error: no cycle to report
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
        if (a.count > (size_t(1) << 32))
            return error(label, std::to_string(a.count) + " elements are more than any buffer view holds"), Span{};
        // tinygltf reads byteOffset as any 64-bit value: one near 2^64 would wrap the sum below
        // past the check, so it is held to the view first.
        if (a.byteOffset > view.byteLength)
            return error(label, "byteOffset " + std::to_string(a.byteOffset) + " lies outside its buffer view of " +
                                    std::to_string(view.byteLength) + " bytes"), Span{};
        // glTF requires each element's components aligned to their size, in the view and in the
        // buffer: a file that is not was written wrongly, and read as it is it draws garbage.
        const int componentBytes = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
        if (componentBytes > 0 && ((a.byteOffset % size_t(componentBytes)) != 0 ||
                                   ((view.byteOffset + a.byteOffset) % size_t(componentBytes)) != 0))
            return error(label, "byteOffset " + std::to_string(a.byteOffset) + " (" +
                                    std::to_string(view.byteOffset + a.byteOffset) + " into its buffer) is not a " +
                                    "multiple of its components' " + std::to_string(componentBytes) +
                                    " bytes, as glTF requires"), Span{};
        // byteOffset <= the view's length <= its buffer's, count <= 2^32 and the schema check holds
        // byteStride to 252: no overflow in size_t.
        const size_t needed = a.byteOffset + stride * (a.count - 1) + elementBytes;
        if (needed > view.byteLength)
            return error(label, std::to_string(a.count) + " elements need " + std::to_string(needed) +
                                    " bytes of its buffer view, which has " + std::to_string(view.byteLength)), Span{};
        return Span{buffer.data() + view.byteOffset + a.byteOffset, stride, a.count};
    }

    /// `index`'s elements as `format.components` doubles each; normalized integers become [0, 1]
    /// (glTF 2.0, "Accessor data types"). Empty (with an error) for another type or a
    /// non-finite element.
    std::vector<double> readAttribute(int index, const AttributeFormat& format, const std::string& what) {
        const std::string label = index >= 0 ? at("accessors", size_t(index)) + " (" + what + ")" : what;
        size_t componentBytes = 4;
        if (index >= 0 && size_t(index) < model_.accessors.size()) {
            const tinygltf::Accessor& a = model_.accessors[size_t(index)];
            const bool integers = format.normalizedIntegers && a.normalized;
            componentBytes = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT && !a.normalized ? 4
                             : integers && a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                             : integers && a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 1
                                                                                                    : 0;
            if (a.type != format.type || componentBytes == 0)
                return error(label, std::string("must be ") + format.expected), std::vector<double>{};
        }
        const Span s = elements(index, format.components * componentBytes, what);
        std::vector<double> out(s.count * format.components);
        for (size_t i = 0; i < s.count; ++i)
            for (size_t c = 0; c < format.components; ++c) {
                const unsigned char* bytes = s.data + i * s.stride + c * componentBytes;
                double& value = out[i * format.components + c];
                if (componentBytes == 4) {
                    float f = 0.0f;
                    std::memcpy(&f, bytes, sizeof f);
                    value = f;
                } else if (componentBytes == 2) {
                    uint16_t u = 0;
                    std::memcpy(&u, bytes, sizeof u);
                    value = u / 65535.0;
                } else {
                    value = *bytes / 255.0;
                }
                if (!std::isfinite(value))
                    return error(label, "element " + std::to_string(i) + " is not finite"), std::vector<double>{};
            }
        return out;
    }

    /// The primitive's attribute `format.name`, one element per position; empty when it has none.
    std::vector<double> attribute(const tinygltf::Primitive& prim, const AttributeFormat& format, size_t positions,
                                  const std::string& path) {
        const auto found = prim.attributes.find(format.name);
        if (found == prim.attributes.end()) return {};
        const std::string what = std::string(format.name) + " of " + path;
        std::vector<double> values = readAttribute(found->second, format, what);
        if (!failed_ && values.size() != positions * format.components)
            error(at("accessors", size_t(found->second)) + " (" + what + ")",
                  std::to_string(values.size() / format.components) + " " + format.noun + "s for " +
                      std::to_string(positions) + " positions");
        return values;
    }

    /// An error unless each of `vectors` (the primitive's NORMAL or TANGENT xyz) has a length.
    void requireLengths(const std::vector<dvec3>& vectors, const tinygltf::Primitive& prim,
                        const AttributeFormat& format, const std::string& path) {
        for (size_t i = 0; i < vectors.size(); ++i)
            if (!(glm::length(vectors[i]) > 1e-6))
                return error(at("accessors", size_t(prim.attributes.at(format.name))) + " (" + format.name +
                                 " of " + path + ")",
                             std::string(format.noun) + " " + std::to_string(i) + " has length " +
                                 std::to_string(glm::length(vectors[i])) + "; " + format.noun +
                                 "s must be unit vectors");
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
        const dmat3 normalMatrix = normalMatrixOf(linear);
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
            const std::vector<dvec3> positions =
                vec3s(readAttribute(position->second, kPosition, "POSITION of " + path), 3);
            if (failed_) return;
            const std::vector<dvec3> normals = vec3s(attribute(prim, kNormal, positions.size(), path), 3);
            const std::vector<double> uvs = attribute(prim, kTexCoord, positions.size(), path);
            const std::vector<double> tangents = attribute(prim, kTangent, positions.size(), path);
            if (failed_) return;
            requireLengths(normals, prim, kNormal, path);
            requireLengths(vec3s(tangents, 4), prim, kTangent, path);
            if (failed_) return;
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
            MeshPrimitive out;
            out.material = materials_.read(prim.material, path + ".material");
            out.name = path;
            if (failed_) return;
            // MASK: a primitive whose alpha is below the cutoff everywhere draws nothing.
            const MeshMaterial& material = out.material;
            if (material.alphaMode == MeshAlphaMode::Mask && material.baseColor[3] < material.alphaCutoff) continue;
            if (samplesTextures(material) && uvs.empty())
                return error(path, "its material samples textures, but it has no TEXCOORD_0");
            materials_.use(out.material, mesh_.images);
            if (failed_) return;
            const size_t newVertices = normals.empty() ? indices.size() : positions.size();
            if (mesh_.vertices.size() + newVertices > limits_.maxVertices ||
                mesh_.indices.size() + indices.size() > limits_.maxIndices)
                return error(path, "the file has more than " + std::to_string(limits_.maxVertices) + " vertices or " +
                                       std::to_string(limits_.maxIndices) + " indices");
            const auto base = uint32_t(mesh_.vertices.size());
            const auto place = [&](size_t i, const dvec3& localNormal) {
                dvec3 wp = dvec3(world * glm::dvec4(positions[i], 1.0));
                // Finite in the file, the transforms can still carry it past what a float holds.
                // The mesh is refused; the vertex stays, at the origin, so that the indices and
                // tangents after it still find one.
                if (!finite(dvec3(glm::vec3(wp)))) {
                    if (!failed_)
                        error(path, "vertex " + std::to_string(i) +
                                        " lies past the range of a float once the node and scene transforms place it");
                    wp = dvec3(0.0);
                }
                const dvec3 transformed = normalMatrix * localNormal;
                // Zero where the transform flattens the surface edge-on, or to a line or a point:
                // nothing of it shows, and any normal does.
                const double length = glm::length(transformed);
                const bool shows = length > 0.0 && std::isfinite(length);
                const dvec3 wn = shows ? glm::normalize(transformed) : dvec3(0.0, 1.0, 0.0);
                MeshVertex v{{float(wp.x), float(wp.y), float(wp.z)}, {float(wn.x), float(wn.y), float(wn.z)}, {}, {}};
                if (!uvs.empty()) {
                    v.uv[0] = float(uvs[2 * i]);
                    v.uv[1] = float(uvs[2 * i + 1]);
                }
                // A tangent is a direction along the surface: the world matrix carries it as it does
                // the positions, and mirroring turns the bitangent's handedness.
                if (!tangents.empty()) {
                    const dvec3 t = linear * dvec3(tangents[4 * i], tangents[4 * i + 1], tangents[4 * i + 2]);
                    setTangent(v, tangentTo(wn, t), (tangents[4 * i + 3] < 0.0) != mirrored ? -1.0 : 1.0);
                }
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
                    for (size_t k = 0; k < 3; ++k) place(indices[t + k], n);
                    for (uint32_t k = 0; k < 3; ++k) mesh_.indices.push_back(base + uint32_t(t) + (mirrored ? 2 - k : k));
                }
            } else {
                for (size_t i = 0; i < positions.size(); ++i) place(i, normals[i]);
                for (size_t t = 0; t < indices.size(); t += 3)
                    for (uint32_t k = 0; k < 3; ++k) mesh_.indices.push_back(base + indices[t + (mirrored ? 2 - k : k)]);
            }
            if (tangents.empty()) deriveTangents(base, out.firstIndex, !uvs.empty());
            out.indexCount = uint32_t(indices.size());
            mesh_.primitives.push_back(std::move(out));
        }
    }

    /// Tangents for the vertices from `firstVertex` on, which the indices from `firstIndex` on
    /// draw, from their world positions and UVs: each triangle's dP/du and dP/dv (Lengyel's
    /// method), summed at its corners. glTF's bitangent points up the image, where v falls (the
    /// first row is at v = 0), so w compares cross(n, t) with -dP/dv: MikkTSpace run on glTF's
    /// UVs as they are gives the opposite sign of the TANGENTs that exporters write.
    void deriveTangents(size_t firstVertex, size_t firstIndex, bool hasUvs) {
        std::vector<MeshVertex>& vertices = mesh_.vertices;
        std::vector<dvec3> alongU(vertices.size() - firstVertex), upTheImage(vertices.size() - firstVertex);
        const auto position = [&](uint32_t i) {
            return dvec3(vertices[i].position[0], vertices[i].position[1], vertices[i].position[2]);
        };
        const auto uv = [&](uint32_t i) { return glm::dvec2(vertices[i].uv[0], vertices[i].uv[1]); };
        for (size_t t = firstIndex; hasUvs && t < mesh_.indices.size(); t += 3) {
            const uint32_t a = mesh_.indices[t], b = mesh_.indices[t + 1], c = mesh_.indices[t + 2];
            const dvec3 e1 = position(b) - position(a), e2 = position(c) - position(a);
            const glm::dvec2 d1 = uv(b) - uv(a), d2 = uv(c) - uv(a);
            const double det = d1.x * d2.y - d2.x * d1.y;
            const dvec3 dPdu = (e1 * d2.y - e2 * d1.y) / det, dPdv = (e2 * d1.x - e1 * d2.x) / det;
            if (!finite(dPdu) || !finite(dPdv)) continue;  // UVs that do not span the triangle (det = 0)
            for (const uint32_t corner : {a, b, c}) {
                alongU[corner - firstVertex] += dPdu;
                upTheImage[corner - firstVertex] -= dPdv;
            }
        }
        for (size_t i = firstVertex; i < vertices.size(); ++i) {
            const dvec3 n = glm::normalize(dvec3(vertices[i].normal[0], vertices[i].normal[1], vertices[i].normal[2]));
            const dvec3 t = tangentTo(n, alongU[i - firstVertex]);
            setTangent(vertices[i], t, glm::dot(glm::cross(n, t), upTheImage[i - firstVertex]) < 0.0 ? -1.0 : 1.0);
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
    const GltfLimits limits_;
    Diagnostics& diagnostics_;
    GltfMaterials materials_;
    TriangleMesh mesh_;
    std::vector<bool> onPath_;
    std::vector<bool> visited_;
    bool failed_ = false;
};

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
                                               Diagnostics& diagnostics, const GltfLimits& limits) {
    const auto fail = [&](const std::string& message) {
        diagnostics.add(Diagnostic{name, "", "", "", message});
        return std::nullopt;
    };
    if (bytes.size() > std::numeric_limits<unsigned>::max()) return fail("is larger than 4 GiB");
    const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    if (binary)
        if (const std::string problem = glbProblem(bytes); !problem.empty()) return fail(problem);
    const std::string json(binary ? glbJsonChunk(bytes) : bytes);
    if (!checkGltfJsonTypes(json, name, binary, diagnostics)) return std::nullopt;
    tinygltf::TinyGLTF reader;
    tinygltf::Model model;
    ImageHeaderCheck headerCheck{&model, limits.maxTextureSide, baseDir, {}};
    reader.SetImageLoader(checkImageHeader, &headerCheck);
    ExternalFiles files{baseDir.string(), {}, urisWithPlus(json)};
    reader.SetFsCallbacks({fileExists, tinygltf::ExpandFilePath, readRegularFile, tinygltf::WriteWholeFile, &files});
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
        // tinygltf quotes what it failed to read, a data URI whole (megabytes of base64).
        constexpr size_t kLongestLine = 240;
        for (std::string line; std::getline(lines, line);) {
            if (line.size() > kLongestLine) {
                size_t cut = kLongestLine;  // not inside a UTF-8 character
                while (cut > 0 && (static_cast<unsigned char>(line[cut]) & 0xC0) == 0x80) --cut;
                line = line.substr(0, cut) + "... (" + std::to_string(line.size() - cut) + " more bytes)";
            }
            if (!line.empty()) diagnostics.add(Diagnostic{name, "", "", "", "glTF: " + line});
        }
        if (diagnostics.size() == before) fail("glTF: tinygltf could not read it");
    }
    // Nothing samples an image that only an ignored extension names: no reason to refuse the file.
    const std::vector<bool> onlyForExtensions = imagesOnlyExtensionsName(model);
    std::erase_if(headerCheck.problems, [&](const auto& entry) {
        return size_t(entry.first) < onlyForExtensions.size() && onlyForExtensions[size_t(entry.first)];
    });
    for (const auto& [index, problem] : headerCheck.problems)
        diagnostics.add(Diagnostic{name, problem.jsonPath, "", "", problem.message});
    if (!read || !error.empty() || !headerCheck.problems.empty()) return std::nullopt;
    std::optional<TriangleMesh> mesh =
        GltfFlattener(name, model, baseDir, limits, diagnostics).flatten(transformMatrix(transform));
    if (mesh) mesh->referencedFiles = std::move(files.read);
    return mesh;
}

std::optional<TriangleMesh> loadGltf(const std::filesystem::path& path, const MeshTransform& transform,
                                     Diagnostics& diagnostics, const GltfLimits& limits) {
    const auto fail = [&](const std::string& message) {
        diagnostics.add(Diagnostic{path.string(), "", "", "", message});
        return std::nullopt;
    };
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return fail("does not exist or is not a file");
    const std::string extension = lowercaseExtension(path);
    if (extension != ".gltf" && extension != ".glb") return fail("is neither a .gltf nor a .glb file");
    // Inserting no bytes sets failbit: an empty file is said to be one, not unreadable.
    if (std::filesystem::file_size(path, ec) == 0 && !ec) return fail("is empty (0 bytes)");
    std::ifstream in(path, std::ios::binary);
    if (!in) return fail("cannot be opened");
    std::ostringstream bytes;
    if (!(bytes << in.rdbuf())) return fail("cannot be read");
    // A .glb is never read as JSON: its first bytes would be reported as a JSON syntax error.
    if (extension == ".glb" && bytes.view().substr(0, 4) != "glTF")
        return fail("is not a binary glTF: a .glb starts with the bytes 'glTF'");
    std::optional<TriangleMesh> mesh = loadGltfFromMemory(bytes.str(), path.string(),
                                                          std::filesystem::absolute(path, ec).parent_path(), transform,
                                                          diagnostics, limits);
    if (mesh) mesh->file = std::filesystem::absolute(path, ec);
    return mesh;
}

}  // namespace skygraph
