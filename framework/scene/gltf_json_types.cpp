// checkGltfJsonTypes: see gltf_json_types.hpp. The rules follow the property names of the
// glTF 2.0 schema, which mean the same wherever they appear, with the few that mean two things
// (`nodes`, `scale`, `target`) accepting both.
#include "gltf_json_types.hpp"

#include "json_path.hpp"
#include "json_positions.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <initializer_list>
#include <cstring>
#include <set>
#include <system_error>

namespace skygraph {
namespace {

using nlohmann::json;

const std::set<std::string, std::less<>> kIndexKeys{
    "scene", "mesh", "camera", "skin", "material", "indices", "bufferView", "buffer", "byteOffset", "byteLength",
    "byteStride", "count", "componentType", "mode", "texCoord", "source", "sampler", "input", "output", "node",
    "index", "magFilter", "minFilter", "wrapS", "wrapT", "inverseBindMatrices"};
const std::set<std::string, std::less<>> kNumberKeys{"strength", "alphaCutoff", "metallicFactor", "roughnessFactor",
                                                     "yfov", "znear", "zfar", "aspectRatio", "xmag", "ymag"};
const std::set<std::string, std::less<>> kNumberArrayKeys{"baseColorFactor", "emissiveFactor", "matrix", "rotation",
                                                          "translation", "min", "max", "weights"};
const std::set<std::string, std::less<>> kObjectKeys{
    "pbrMetallicRoughness", "normalTexture", "occlusionTexture", "emissiveTexture", "baseColorTexture",
    "metallicRoughnessTexture", "attributes", "perspective", "orthographic", "sparse", "asset", "values"};
const std::set<std::string, std::less<>> kStringKeys{"name", "uri", "mimeType", "type", "alphaMode", "version",
                                                     "generator", "minVersion", "copyright", "interpolation", "path"};
const std::set<std::string, std::less<>> kTopLevelArrays{
    "scenes", "nodes", "meshes", "materials", "accessors", "bufferViews", "buffers", "textures", "images",
    "samplers", "cameras", "skins", "animations"};

class TypeChecker {
public:
    TypeChecker(std::string file, Diagnostics& diagnostics) : file_(std::move(file)), diagnostics_(diagnostics) {}

    bool check(const json& root) {
        if (!root.is_object()) return error("", "a glTF file must be a JSON object"), false;
        for (const auto& [key, value] : root.items()) {
            if (kTopLevelArrays.count(key)) {
                if (!value.is_array()) { error(key, "must be an array of objects, got " + kind(value)); continue; }
                for (size_t i = 0; i < value.size(); ++i) object(value[i], key + "[" + std::to_string(i) + "]");
            } else if (key == "extensionsUsed" || key == "extensionsRequired") {
                if (!value.is_array()) error(key, "must be an array of strings, got " + kind(value));
                else for (size_t i = 0; i < value.size(); ++i)
                    if (!value[i].is_string()) error(key + "[" + std::to_string(i) + "]", "must be a string, got " + kind(value[i]));
            } else {
                property(key, value, key);
            }
        }
        return ok_;
    }

private:
    void error(const std::string& path, const std::string& message) {
        diagnostics_.add(Diagnostic{file_, path, "", "", message});
        ok_ = false;
    }

    static std::string kind(const json& v) {
        const std::string text = v.dump();
        return std::string(v.type_name()) + " " + (text.size() > 40 ? text.substr(0, 40) + "..." : text);
    }

    void object(const json& v, const std::string& path) {
        if (!v.is_object()) return error(path, "must be an object, got " + kind(v));
        for (const auto& [key, value] : v.items()) property(key, value, jsonPathMember(path, key));
    }

    void indexArray(const json& v, const std::string& path) {
        if (!v.is_array()) return error(path, "must be an array of indices, got " + kind(v));
        for (size_t i = 0; i < v.size(); ++i)
            if (!v[i].is_number_unsigned()) error(path + "[" + std::to_string(i) + "]", "must be an index (an integer >= 0), got " + kind(v[i]));
    }

    void property(const std::string& key, const json& v, const std::string& path) {
        if (key == "extras") return;  // anything
        if (key == "extensions") {
            if (!v.is_object()) return error(path, "must be an object, got " + kind(v));
            for (const auto& [name, ext] : v.items())
                if (!ext.is_object()) error(jsonPathMember(path, name), "an extension must be an object, got " + kind(ext));
            return;
        }
        // An accessor's sparse storage names its own `indices` and `values` objects; the loader
        // refuses sparse accessors with that said, so only their shape is checked here.
        if (key == "sparse") {
            if (!v.is_object()) error(path, "must be an object, got " + kind(v));
            return;
        }
        if (kIndexKeys.count(key)) {
            if (!v.is_number_unsigned()) error(path, "must be an integer >= 0, got " + kind(v));
        } else if (kNumberKeys.count(key)) {
            if (!v.is_number()) error(path, "must be a number, got " + kind(v));
        } else if (kNumberArrayKeys.count(key)) {
            if (!v.is_array()) return error(path, "must be an array of numbers, got " + kind(v));
            for (size_t i = 0; i < v.size(); ++i)
                if (!v[i].is_number()) error(path + "[" + std::to_string(i) + "]", "must be a number, got " + kind(v[i]));
        } else if (kStringKeys.count(key)) {
            if (!v.is_string()) error(path, "must be a string, got " + kind(v));
        } else if (key == "scale") {  // a texture's factor, or a node's three
            if (v.is_array()) property("translation", v, path);
            else if (!v.is_number()) error(path, "must be a number or an array of numbers, got " + kind(v));
        } else if (key == "target") {  // a buffer view's binding, or an animation channel's object
            if (v.is_object()) object(v, path);
            else if (!v.is_number_unsigned()) error(path, "must be an integer >= 0 or an object, got " + kind(v));
        } else if (key == "nodes" || key == "children" || key == "joints") {
            indexArray(v, path);
        } else if (key == "primitives" || key == "targets" || key == "channels") {
            if (!v.is_array()) return error(path, "must be an array of objects, got " + kind(v));
            for (size_t i = 0; i < v.size(); ++i) object(v[i], path + "[" + std::to_string(i) + "]");
        } else if (key == "attributes") {
            if (!v.is_object()) return error(path, "must be an object of accessor indices, got " + kind(v));
            for (const auto& [name, index] : v.items())
                if (!index.is_number_unsigned()) error(jsonPathMember(path, name), "must be an accessor index (an integer >= 0), got " + kind(index));
        } else if (kObjectKeys.count(key)) {
            object(v, path);
        }
    }

    std::string file_;
    Diagnostics& diagnostics_;
    bool ok_ = true;
};

}  // namespace

namespace {

/// The values the glTF 2.0 schema allows where tinygltf either says no more than the property
/// (`componentType`, `type`, `byteStride`, the factors' lengths) or keeps a wrong one (a node's
/// `matrix` of three numbers is read as the identity). Runs once the types are right. Material
/// values (`alphaMode`, ranges, wrap modes) are checked where the materials are read.
class ValueChecker {
public:
    ValueChecker(std::string file, bool binary, Diagnostics& diagnostics)
        : file_(std::move(file)), binary_(binary), diagnostics_(diagnostics) {}

    bool check(const json& root) {
        // tinygltf names a missing property without saying where, and reads any version.
        const auto asset = root.find("asset");
        if (asset == root.end()) {
            error("asset", "missing; a glTF file says its version there");
        } else if (const auto version = asset->find("version"); version == asset->end()) {
            error("asset.version", "missing; expected \"2.0\"");
        } else if (version->get<std::string>().rfind("2.", 0) != 0) {
            error("asset.version", "skygraph reads glTF 2.x, got " + version->dump());
        } else if (const auto min = asset->find("minVersion"); min != asset->end() && min->get<std::string>() != "2.0") {
            error("asset.minVersion", "skygraph reads glTF 2.0, got " + min->dump());
        }
        // Before tinygltf reads the file: what an extension changes (Draco's compressed
        // buffers) would fail there with a message about its effect, not its cause.
        if (const auto required = root.find("extensionsRequired"); required != root.end())
            for (const json& ext : *required)
                error("extensionsRequired", "the file requires extension '" + ext.get<std::string>() +
                                                "', which skygraph does not support");
        if (!ok_) return false;
        const size_t views = root.contains("bufferViews") ? root["bufferViews"].size() : 0;
        each(root, "accessors", [&](const json& a, const std::string& at) {
            required(a, at, {"componentType", "count", "type"});
            if (const auto view = a.find("bufferView"); view != a.end() && view->get<uint64_t>() >= views)
                error(at + ".bufferView", "buffer view " + view->dump() + " does not exist");
            oneOf(a, "componentType", at, {5120, 5121, 5122, 5123, 5125, 5126},
                  "BYTE (5120), UNSIGNED_BYTE (5121), SHORT (5122), UNSIGNED_SHORT (5123), UNSIGNED_INT (5125) or FLOAT (5126)");
            oneOf(a, "type", at, {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"});
            if (const auto sparse = a.find("sparse"); sparse != a.end())
                if (const auto indices = sparse->find("indices"); indices != sparse->end())
                    oneOf(*indices, "componentType", at + ".sparse.indices", {5121, 5123, 5125},
                          "UNSIGNED_BYTE (5121), UNSIGNED_SHORT (5123) or UNSIGNED_INT (5125)");
        });
        each(root, "bufferViews", [&](const json& v, const std::string& at) {
            required(v, at, {"buffer", "byteLength"});
            if (const auto stride = v.find("byteStride"); stride != v.end()) {
                const uint64_t s = stride->get<uint64_t>();
                if (s < 4 || s > 252 || s % 4 != 0)
                    error(at + ".byteStride", "must be a multiple of 4 from 4 to 252, got " + std::to_string(s));
            }
        });
        each(root, "nodes", [&](const json& n, const std::string& at) {
            length(n, "matrix", at, 16);
            length(n, "rotation", at, 4);
            length(n, "translation", at, 3);
            length(n, "scale", at, 3);
            if (n.contains("matrix") && (n.contains("rotation") || n.contains("translation") || n.contains("scale")))
                error(at, "has both a matrix and rotation, translation or scale; glTF allows one or the other");
        });
        each(root, "buffers", [&](const json& b, const std::string& at) {
            required(b, at, {"byteLength"});
            // Only a .glb's first buffer, its binary chunk, has no uri.
            if (!b.contains("uri") && !(binary_ && at == "buffers[0]"))
                error(at + ".uri", "missing; only the first buffer of a .glb may have none");
            relativeUri(b, at);
        });
        each(root, "images", [&](const json& i, const std::string& at) { relativeUri(i, at); });
        const size_t accessors = root.contains("accessors") ? root["accessors"].size() : 0;
        each(root, "meshes", [&](const json& m, const std::string& at) {
            required(m, at, {"primitives"});
            if (const auto primitives = m.find("primitives"); primitives != m.end())
                for (size_t i = 0; i < primitives->size(); ++i) {
                    const std::string p = at + ".primitives[" + std::to_string(i) + "]";
                    required((*primitives)[i], p, {"attributes"});
                    // tinygltf says only "primitive indices accessor out of bounds", nowhere.
                    if (const auto indices = (*primitives)[i].find("indices");
                        indices != (*primitives)[i].end() && indices->get<uint64_t>() >= accessors)
                        error(p + ".indices", "accessor " + indices->dump() + " does not exist");
                    if ((*primitives)[i].contains("mode") && (*primitives)[i]["mode"].get<uint64_t>() > 6)
                        error(p + ".mode", "must be a primitive mode from 0 to 6, got " + (*primitives)[i]["mode"].dump());
                }
        });
        each(root, "materials", [&](const json& m, const std::string& at) {
            length(m, "emissiveFactor", at, 3);
            if (const auto pbr = m.find("pbrMetallicRoughness"); pbr != m.end())
                length(*pbr, "baseColorFactor", at + ".pbrMetallicRoughness", 4);
        });
        // tinygltf says "Orthographic camera description not found." and the like, naming no camera.
        each(root, "cameras", [&](const json& c, const std::string& at) {
            required(c, at, {"type"});
            oneOf(c, "type", at, {"perspective", "orthographic"});
            const auto type = c.find("type");
            if (type == c.end()) return;
            const std::string projection = type->get<std::string>();
            if (projection != "perspective" && projection != "orthographic") return;
            const auto description = c.find(projection);
            if (description == c.end())
                return error(at + "." + projection,
                             "missing; a camera of type \"" + projection + "\" describes its projection there");
            if (projection == "perspective") required(*description, at + ".perspective", {"yfov", "znear"});
            else required(*description, at + ".orthographic", {"xmag", "ymag", "zfar", "znear"});
        });
        return ok_;
    }

private:
    void error(const std::string& path, const std::string& message) {
        diagnostics_.add(Diagnostic{file_, path, "", "", message});
        ok_ = false;
    }

    void required(const json& object, const std::string& at, std::initializer_list<const char*> keys) {
        for (const char* key : keys)
            if (!object.contains(key)) error(at + "." + key, "missing; glTF requires it here");
    }

    /// tinygltf joins an absolute path to the glTF's folder too, and says "File not found", or
    /// for an image only warns.
    void relativeUri(const json& object, const std::string& at) {
        if (const auto uri = object.find("uri"); uri != object.end() && !uri->get<std::string>().starts_with("data:"))
            if (const std::string problem = absoluteUriProblem(uri->get<std::string>()); !problem.empty())
                error(at + ".uri", problem);
    }

    template <typename F>
    static void each(const json& root, const char* array, F&& f) {
        if (const auto a = root.find(array); a != root.end())
            for (size_t i = 0; i < a->size(); ++i) f((*a)[i], std::string(array) + "[" + std::to_string(i) + "]");
    }

    void length(const json& object, const char* key, const std::string& at, size_t expected) {
        if (const auto v = object.find(key); v != object.end() && v->size() != expected)
            error(at + "." + key, "must be an array of " + std::to_string(expected) + " numbers, got " +
                                      std::to_string(v->size()));
    }

    void oneOf(const json& object, const char* key, const std::string& at, std::initializer_list<uint64_t> allowed,
               const char* names) {
        if (const auto v = object.find(key); v != object.end() && std::find(allowed.begin(), allowed.end(), v->get<uint64_t>()) == allowed.end())
            error(at + "." + key, "must be " + std::string(names) + ", got " + v->dump());
    }

    void oneOf(const json& object, const char* key, const std::string& at, std::initializer_list<std::string_view> allowed) {
        const auto v = object.find(key);
        if (v == object.end() || std::find(allowed.begin(), allowed.end(), v->get<std::string>()) != allowed.end()) return;
        std::string names;
        for (const std::string_view name : allowed)
            names += (names.empty() ? "\"" : name == *std::prev(allowed.end()) ? " or \"" : ", \"") + std::string(name) + "\"";
        error(at + "." + key, "must be " + names + ", got " + v->dump());
    }

    std::string file_;
    bool binary_;
    Diagnostics& diagnostics_;
    bool ok_ = true;
};

}  // namespace

std::string glbProblem(std::string_view data) {
    const auto word = [&](size_t at) {
        uint32_t v = 0;
        std::memcpy(&v, data.data() + at, 4);
        return v;
    };
    const std::string size = std::to_string(data.size());
    if (data.size() < 12) return "truncated: a .glb starts with a 12-byte header; the file has " + size + " bytes";
    if (word(4) != 2) return "GLB version " + std::to_string(word(4)) + "; skygraph reads version 2";
    if (word(8) > data.size()) return "truncated: its header says " + std::to_string(word(8)) + " bytes, the file has " + size;
    if (data.size() < 20) return "truncated: no chunk follows the header";
    if (data.compare(16, 4, "JSON") != 0) return "its first chunk is not the JSON chunk";
    if (word(12) == 0) return "its JSON chunk is empty";
    if (uint64_t(word(12)) + 20 > word(8))
        return "truncated: its JSON chunk says " + std::to_string(word(12)) + " bytes, and " +
               std::to_string(word(8) - 20) + " follow within the length its header gives";
    // tinygltf checks the BIN chunk's length without its own 8-byte header, so one up to 8 bytes
    // short passed and was read past the end of the file.
    const uint64_t binChunk = uint64_t(word(12)) + 20, length = word(8);
    if (binChunk < length) {
        if (length - binChunk < 8)
            return "truncated: " + std::to_string(length - binChunk) +
                   " bytes follow the JSON chunk, too few for the BIN chunk's 8-byte header";
        const uint32_t binLength = word(size_t(binChunk));
        if (binLength > length - binChunk - 8)
            return "truncated: its BIN chunk says " + std::to_string(binLength) + " bytes, and " +
                   std::to_string(length - binChunk - 8) + " follow within the length its header gives";
    }
    return {};
}

std::string_view glbJsonChunk(std::string_view data) {
    uint32_t length = 0;
    std::memcpy(&length, data.data() + 12, 4);
    return data.substr(20, length);
}

std::string decodeUri(const std::string& uri, bool plusIsSpace) {
    const auto hex = [](char c) -> unsigned {
        if (c >= '0' && c <= '9') return unsigned(c - '0');
        if (c >= 'a' && c <= 'f') return unsigned(c - 'a' + 10);
        if (c >= 'A' && c <= 'F') return unsigned(c - 'A' + 10);
        return 0;  // tinygltf reads any other character as 0 too
    };
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '+' && plusIsSpace) {
            out += ' ';
        } else if (uri[i] == '%' && uri.size() > i + 2) {
            out += static_cast<char>(hex(uri[i + 1]) << 4 | hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

std::filesystem::path uriFile(const std::filesystem::path& baseDir, const std::string& uri) {
    return baseDir / decodeUri(uri, false);
}

std::string notARegularFile(const std::filesystem::path& path) {
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (status.type() == std::filesystem::file_type::not_found) return "does not exist";
    if (ec) return "cannot be read (" + ec.message() + ")";
    if (std::filesystem::is_directory(status)) return "is a directory";
    if (!std::filesystem::is_regular_file(status)) return "is not a regular file";
    return {};
}

std::string absoluteUriProblem(const std::string& uri) {
    const std::string decoded = decodeUri(uri, false);
    std::string scheme = uri.substr(0, 5);
    std::transform(scheme.begin(), scheme.end(), scheme.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    const char* what = decoded.starts_with('/') ? "an absolute path" : scheme == "file:" ? "a file: URI" : nullptr;
    if (!what) return {};
    return "'" + uri + "' is " + what + "; a glTF uri names a file relative to the glTF file's folder, and absolute "
           "paths are refused";
}

bool checkGltfJsonTypes(const std::string& jsonText, const std::string& file, bool binary, Diagnostics& diagnostics) {
    // The reader that refuses deep nesting: tinygltf's recursion would exhaust the stack.
    const JsonParseResult parsed = parseJsonWithPositions(jsonText);
    if (!parsed.error.empty()) {
        // A .glb's positions would count in its JSON chunk, not in the file.
        Diagnostic d{file, parsed.errorPath, "", "", binary ? "JSON chunk: " + parsed.error : parsed.error};
        if (!binary) {
            d.line = parsed.line;
            d.column = parsed.column;
        }
        diagnostics.add(std::move(d));
        return false;
    }
    for (const DuplicateKey& dup : parsed.duplicateKeys)
        diagnostics.add(Diagnostic{file, dup.path, "", "", "duplicate key '" + dup.key + "'; JSON keeps only the last one"});
    if (!TypeChecker(file, diagnostics).check(parsed.value)) return false;
    return ValueChecker(file, binary, diagnostics).check(parsed.value) && parsed.duplicateKeys.empty();
}

}  // namespace skygraph
