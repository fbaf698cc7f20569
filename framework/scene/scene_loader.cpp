// Scene file -> Scene. Like the graph loader, it collects every problem in the file (each with
// the file and the JSON path) before throwing, so one run shows all of them.
#include "file_extension.hpp"
#include "json_path.hpp"
#include "json_positions.hpp"

#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <system_error>

namespace skygraph {
namespace {

using nlohmann::json;

/// A closed or open interval, printed the way the messages and the schema say it.
struct Range {
    double lo = -HUGE_VAL, hi = HUGE_VAL;
    bool loOpen = false, hiOpen = false;
    [[nodiscard]] bool contains(double v) const {
        return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
    }
    [[nodiscard]] std::string text() const {
        auto num = [](double v) { std::ostringstream o; o << v; return o.str(); };
        if (hi == HUGE_VAL) return std::string(loOpen ? "> " : ">= ") + num(lo);
        return (loOpen ? "in (" : "in [") + num(lo) + ", " + num(hi) + (hiOpen ? ")" : "]");
    }
};
const Range kAny{};
const Range kUnit{0.0, 1.0};
const Range kPositive{0.0, HUGE_VAL, true};
/// The narrowest view: it magnifies view-space positions by 1 / tan(fov / 2), and much past
/// this the float rounding of world positions shows, then the projection leaves a float's
/// range and nothing draws (1e-30 degrees drew part of a sphere, 1e-37 none of it).
constexpr double kNarrowestFovDeg = 1e-3;
/// The depth buffer holds near / distance (reverse-Z, infinite far plane): a nearer plane puts
/// geometry at ordinary distances below a 32-bit float's smallest normal, which GPUs flush to 0,
/// the depth of the sky, and it vanishes (2e-38 does past 1.7 units). 1e-6 keeps every distance
/// below 1e32 in range.
constexpr double kNearestNear = 1e-6;
const std::string kNearTooNear =
    "must be at least 1e-6: depth is near / distance, and a nearer plane leaves distant geometry "
    "below a float's smallest normal, where it vanishes; got ";

/// Whether the loader refused a file for being past `limits` (its messages name them).
bool refusedForLimits(const Diagnostics& problems, const GltfLimits& limits) {
    const std::string vertices = "more than " + std::to_string(limits.maxVertices) + " vertices";
    const std::string imageBytes = "bytes, more than " + std::to_string(limits.maxImageBytes);
    return std::any_of(problems.items().begin(), problems.items().end(), [&](const Diagnostic& d) {
        return d.message.find(vertices) != std::string::npos || d.message.find(imageBytes) != std::string::npos;
    });
}

class SceneLoader {
public:
    SceneLoader(std::string file, std::filesystem::path baseDir, const GltfLimits& limits)
        : baseDir_(std::move(baseDir)), limits_(limits) {
        scene_.file = std::move(file);
    }

    Scene load(std::string_view text) {
        JsonParseResult parsed = parseJsonWithPositions(text);
        if (!parsed.error.empty()) {
            Diagnostic d{scene_.file, parsed.errorPath, "", "", parsed.error};
            d.line = parsed.line;
            d.column = parsed.column;
            diags_.add(std::move(d));
            throw SceneError(std::move(diags_));
        }
        for (const auto& dup : parsed.duplicateKeys)
            error(dup.path, "duplicate key '" + dup.key + "'; JSON keeps only the last one");
        loadRoot(parsed.value);
        if (!diags_.empty()) throw SceneError(std::move(diags_));
        return std::move(scene_);
    }

private:
    void error(const std::string& path, const std::string& message) {
        diags_.add(Diagnostic{scene_.file, path, "", "", message});
    }

    void checkKeys(const json& object, const std::string& path, std::initializer_list<std::string_view> allowed) {
        for (const auto& [key, _] : object.items()) {
            if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
            std::string list;
            for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
            error(jsonPathMember(path, key), "unknown key '" + key + "'; expected one of: " + list);
        }
    }

    /// The GPU reads scenes as 32-bit floats: past their range a value becomes infinite, and
    /// below their normal numbers it loses its precision (or becomes 0).
    static bool floatHolds(double d) {
        return d == 0.0 || (std::abs(d) <= double(std::numeric_limits<float>::max()) &&
                            std::abs(d) >= double(std::numeric_limits<float>::min()));
    }

    /// A finite number in `range` at `path`; false (with an error) otherwise.
    bool number(const json& v, const std::string& path, const Range& range, double& out) {
        if (!v.is_number()) return error(path, "expected a number, got " + v.dump()), false;
        const double d = v.get<double>();
        if (!std::isfinite(d)) return error(path, "must be a finite number"), false;
        if (!floatHolds(d))
            return error(path, "must be 0 or of a magnitude a 32-bit float holds (1.2e-38 to 3.4e38), got " + v.dump()),
                   false;
        if (!range.contains(d)) return error(path, "must be " + range.text() + ", got " + v.dump()), false;
        out = d;
        return true;
    }

    /// Reads optional `key` of `object` into `out`; an absent key leaves the default.
    void optionalNumber(const json& object, const std::string& path, const char* key, const Range& range,
                        double& out) {
        if (auto it = object.find(key); it != object.end()) number(*it, jsonPathMember(path, key), range, out);
    }

    void vec3(const json& v, const std::string& path, const Range& range, std::array<double, 3>& out) {
        if (!v.is_array() || v.size() != 3) return error(path, "expected an array of 3 numbers, got " + v.dump());
        for (size_t i = 0; i < 3; ++i) number(v[i], path + "[" + std::to_string(i) + "]", range, out[i]);
    }

    void requiredVec3(const json& object, const std::string& path, const char* key, std::array<double, 3>& out) {
        if (auto it = object.find(key); it != object.end()) vec3(*it, jsonPathMember(path, key), kAny, out);
        else error(jsonPathMember(path, key), "missing; expected [x, y, z]");
    }

    template <typename Enum>
    void enumeration(const json& object, const std::string& path, const char* key,
                     const std::map<std::string, Enum>& names, Enum& out) {
        auto it = object.find(key);
        if (it == object.end()) return;
        std::string list;
        for (const auto& [n, _] : names) list += (list.empty() ? "" : ", ") + n;
        if (!it->is_string() || !names.count(it->get<std::string>()))
            return error(jsonPathMember(path, key), "expected one of " + list + ", got " + it->dump());
        out = names.at(it->get<std::string>());
    }

    void loadRoot(const json& root) {
        if (!root.is_object()) return error("", "a scene file must be a JSON object");
        checkKeys(root, "", {"$schema", "description", "camera", "environment", "exposure_ev", "tonemapper",
                             "debug_view", "objects"});
        if (auto it = root.find("description"); it != root.end() && !it->is_string())
            error("description", "must be a string");
        bool gltfCamera = false;
        if (auto it = root.find("camera"); it != root.end()) {
            if (it->is_string() && it->get<std::string>() == "gltf") gltfCamera = true;
            else loadCamera(*it);
        }
        if (auto it = root.find("environment"); it != root.end() && !it->is_null()) loadEnvironment(*it);
        optionalNumber(root, "", "exposure_ev", Range{-64.0, 64.0}, scene_.exposureEv);
        enumeration(root, "", "tonemapper",
                    std::map<std::string, Tonemapper>{{"aces_narkowicz", Tonemapper::AcesNarkowicz},
                                                      {"aces_hill", Tonemapper::AcesHill},
                                                      {"khronos_pbr_neutral", Tonemapper::KhronosPbrNeutral},
                                                      {"passthrough", Tonemapper::Passthrough}},
                    scene_.tonemapper);
        enumeration(root, "", "debug_view",
                    std::map<std::string, DebugView>{{"none", DebugView::None}, {"normal", DebugView::Normal},
                                                     {"metallic", DebugView::Metallic},
                                                     {"roughness", DebugView::Roughness}, {"ao", DebugView::Ao}},
                    scene_.debugView);
        if (auto it = root.find("objects"); it != root.end()) {
            if (!it->is_array()) return error("objects", "must be an array of objects");
            // Refused before any is loaded: each glTF object decodes its file, and thousands of
            // them would take the memory the limit is there to keep.
            if (it->size() > kMaxSceneObjects)
                return error("objects", "has " + std::to_string(it->size()) + " objects; at most " +
                                            std::to_string(kMaxSceneObjects) + " are allowed");
            for (size_t i = 0; i < it->size(); ++i) loadObject((*it)[i], "objects[" + std::to_string(i) + "]");
        }
        if (gltfCamera) cameraFromGltf();
    }

    /// `"camera": "gltf"`: the first camera of the first glTF object that has one.
    void cameraFromGltf() {
        // An object that failed to load is not in scene_.objects: its numbers would be off.
        if (!diags_.empty()) return;
        for (size_t i = 0; i < scene_.objects.size(); ++i) {
            const auto* model = std::get_if<GltfModel>(&scene_.objects[i].shape);
            if (!model || !model->mesh->camera) continue;
            const MeshCamera& c = *model->mesh->camera;
            // The position comes out of the node transforms: a coordinate below a float's
            // smallest normal is their rounding about 0, and is 0.
            std::array<double, 3> position = c.position;
            for (double& x : position)
                if (std::abs(x) < double(std::numeric_limits<float>::min())) x = 0.0;
            // What camera.position and camera.near take from the scene file, they take from the glTF.
            const bool holds =
                floatHolds(c.near) && floatHolds(position[0]) && floatHolds(position[1]) && floatHolds(position[2]);
            if (holds && c.near < kNearestNear) {
                char value[32];
                std::snprintf(value, sizeof value, "%.9g", c.near);
                return error("camera", "objects[" + std::to_string(i) + "]'s glTF camera's znear " + kNearTooNear +
                                           value);
            }
            if (!holds) {
                char values[160];
                std::snprintf(values, sizeof values, "position [%.9g, %.9g, %.9g] and near plane %.9g", position[0],
                              position[1], position[2], c.near);
                return error("camera", "objects[" + std::to_string(i) + "]'s glTF camera has the " + values +
                                           ": each must be 0 or of a magnitude a 32-bit float holds (1.2e-38 to "
                                           "3.4e38), as the scene's camera's");
            }
            if (!(c.fovYDeg >= kNarrowestFovDeg)) {
                char values[80];
                std::snprintf(values, sizeof values, "%.9g degrees, narrower than the %g", c.fovYDeg, kNarrowestFovDeg);
                return error("camera", "objects[" + std::to_string(i) + "]'s glTF camera's yfov is " + values +
                                           " degrees a view may be (as the scene's camera's fov_y_deg)");
            }
            SceneCamera& cam = scene_.camera;
            cam.position = position;
            const math::Vec3<double> f(c.forward[0], c.forward[1], c.forward[2]), u(c.up[0], c.up[1], c.up[2]);
            // Inverts math::cameraRotation (R = Ry(yaw) Rx(pitch) Rz(roll)): forward is R (0, 0, -1).
            cam.pitchDeg = glm::degrees(std::asin(std::clamp(f.y, -1.0, 1.0)));
            cam.yawDeg = glm::degrees(std::atan2(-f.x, -f.z));
            const math::Vec3<double> rolled = glm::transpose(math::cameraRotation(cam.yawDeg, cam.pitchDeg, 0.0)) * u;
            cam.rollDeg = glm::degrees(std::atan2(-rolled.x, rolled.y));
            cam.fovYDeg = c.fovYDeg;
            cam.near = c.near;
            return;
        }
        error("camera", "is \"gltf\", but no glTF object of the scene has a perspective camera");
    }

    void loadCamera(const json& c) {
        if (!c.is_object()) return error("camera", "must be an object");
        checkKeys(c, "camera", {"position", "yaw_deg", "pitch_deg", "roll_deg", "fov_y_deg", "near"});
        SceneCamera& cam = scene_.camera;
        if (auto it = c.find("position"); it != c.end()) vec3(*it, "camera.position", kAny, cam.position);
        optionalNumber(c, "camera", "yaw_deg", kAny, cam.yawDeg);
        optionalNumber(c, "camera", "pitch_deg", kAny, cam.pitchDeg);
        optionalNumber(c, "camera", "roll_deg", kAny, cam.rollDeg);
        optionalNumber(c, "camera", "fov_y_deg", Range{kNarrowestFovDeg, 180.0, false, true}, cam.fovYDeg);
        if (auto it = c.find("near"); it != c.end() && number(*it, "camera.near", kPositive, cam.near) &&
                                      cam.near < kNearestNear)
            error("camera.near", kNearTooNear + it->dump());
    }

    void loadEnvironment(const json& e) {
        if (!e.is_object())
            return error("environment",
                         "must be an object {file or sequence, rotation_deg, sampling, sun_direction, fps} or null for none");
        checkKeys(e, "environment", {"file", "sequence", "fps", "rotation_deg", "sampling", "sun_direction"});
        SceneEnvironment env;
        optionalNumber(e, "environment", "rotation_deg", kAny, env.rotationDeg);
        enumeration(e, "environment", "sampling",
                    std::map<std::string, EnvironmentSampling>{{"cubemap", EnvironmentSampling::Cubemap},
                                                               {"equirect", EnvironmentSampling::Equirect}},
                    env.sampling);
        if (e.contains("sequence")) return loadSequence(e, std::move(env));
        if (e.contains("fps")) error("environment.fps", "only a sequence has a frame rate; this environment has none");
        auto file = e.find("file");
        if (file == e.end() || !file->is_string() || file->get<std::string>().empty())
            return error("environment.file", std::string(file == e.end() ? "missing" : "not a file name") +
                                                 "; expected \"procedural\" or a .hdr/.exr path");
        const std::string name = file->get<std::string>();
        if (auto sun = e.find("sun_direction"); sun != e.end()) {
            Vec3 v{};
            vec3(*sun, "environment.sun_direction", kAny, v);
            // Scaled by its largest component first: the length of [1e-20, 1e-20, 1e-20] squares
            // to below a double's range.
            const double largest = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
            if (name != "procedural")
                error("environment.sun_direction", "only the procedural sky has a sun; this environment is a file");
            else if (!(largest > 0.0))
                error("environment.sun_direction", "must not be the zero vector");
            else {
                const double len = std::hypot(v[0] / largest, v[1] / largest, v[2] / largest);
                for (size_t i = 0; i < 3; ++i) env.sunDirection[i] = v[i] / largest / len;
            }
        }
        if (name != "procedural") {
            env.procedural = false;
            env.file = (baseDir_ / name).lexically_normal();  // an absolute name replaces baseDir_
            const std::string ext = lowercaseExtension(env.file);
            std::error_code ec;
            if (ext != ".hdr" && ext != ".exr")
                error("environment.file", "'" + name + "' is neither \"procedural\" nor a .hdr or .exr file");
            else if (!std::filesystem::is_regular_file(env.file, ec))
                error("environment.file", "'" + env.file.string() + "' does not exist or is not a file");
        }
        scene_.environment = std::move(env);
    }

    void loadSequence(const json& e, SceneEnvironment env) {
        if (e.contains("file")) error("environment.file", "a sequence's frames are its files: give file or sequence, not both");
        if (e.contains("sun_direction"))
            error("environment.sun_direction", "only the procedural sky has a sun; this environment is a sequence");
        EnvironmentSequence sequence;
        optionalNumber(e, "environment", "fps", Range{0.0, 1000.0, true, false}, sequence.fps);
        const json& name = e.at("sequence");
        if (!name.is_string() || name.get<std::string>().empty())
            return error("environment.sequence", "must be a file pattern such as \"frames/%04d.exr\"");
        const std::string text = name.get<std::string>();
        if (const std::string problem = sequencePatternProblem(std::filesystem::path(text).filename().string());
            !problem.empty())
            return error("environment.sequence", "'" + text + "': its file name " + problem);
        sequence.pattern = (baseDir_ / text).lexically_normal().string();
        const std::string ext = lowercaseExtension(text);
        if (ext != ".hdr" && ext != ".exr")
            return error("environment.sequence", "'" + text + "' names neither .hdr nor .exr files");
        std::error_code ec;
        // A folder (or anything but a file) named like a frame would end the sequence there,
        // or start it at frame 1, without a word.
        std::filesystem::path notAFrame;
        const auto exists = [&](uint32_t number) {
            const std::filesystem::path frame = sequenceFrameFile(sequence.pattern, number);
            const std::filesystem::file_status status = std::filesystem::status(frame, ec);
            if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) && notAFrame.empty())
                notAFrame = frame;
            return std::filesystem::is_regular_file(status);
        };
        const auto refuseNotAFrame = [&] {
            error("environment.sequence", "'" + notAFrame.string() + "' is named like a frame but is " +
                                              (std::filesystem::is_directory(notAFrame, ec) ? "a folder" : "not a file"));
        };
        if (!exists(0) && !exists(1)) {
            if (!notAFrame.empty()) return refuseNotAFrame();
            return error("environment.sequence", "no first frame: neither '" +
                                                     sequenceFrameFile(sequence.pattern, 0).string() + "' nor '" +
                                                     sequenceFrameFile(sequence.pattern, 1).string() + "' exists");
        }
        sequence.first = exists(0) ? 0 : 1;
        while (sequence.count < kMaxSequenceFrames && exists(sequence.first + sequence.count)) ++sequence.count;
        if (!notAFrame.empty()) return refuseNotAFrame();
        if (exists(sequence.first + sequence.count))
            return error("environment.sequence", "more than " + std::to_string(kMaxSequenceFrames) + " frames");
        env.procedural = false;
        env.file = sequence.frame(0);
        env.sequence = std::move(sequence);
        scene_.environment = std::move(env);
    }

    void loadObject(const json& o, const std::string& path) {
        if (!o.is_object()) return error(path, "must be an object with a type");
        auto type = o.find("type");
        const std::string t = type != o.end() && type->is_string() ? type->get<std::string>() : "";
        SceneObject obj;
        if (t == "sphere") {
            checkKeys(o, path, {"type", "center", "radius", "material"});
            Sphere s;
            requiredVec3(o, path, "center", s.center);
            if (auto it = o.find("radius"); it != o.end()) number(*it, path + ".radius", kPositive, s.radius);
            else error(path + ".radius", "missing; expected a number > 0");
            obj.shape = s;
        } else if (t == "plane") {
            checkKeys(o, path, {"type", "point", "normal", "half_extent", "material"});
            Plane p;
            requiredVec3(o, path, "point", p.point);
            requiredVec3(o, path, "normal", p.normal);
            const double len = std::hypot(p.normal[0], p.normal[1], p.normal[2]);
            if (!(len > 1e-12)) error(path + ".normal", "must not be the zero vector");
            else for (double& c : p.normal) c /= len;
            double half = 1.0;
            if (o.contains("half_extent") && number(o["half_extent"], path + ".half_extent", kPositive, half))
                p.halfExtent = half;
            obj.shape = p;
        } else if (t == "gltf") {
            checkKeys(o, path, {"type", "file", "transform"});
            return loadGltfObject(o, path);
        } else {
            return error(path + ".type", "expected \"sphere\", \"plane\" or \"gltf\", got " +
                                             (type == o.end() ? std::string("nothing") : type->dump()));
        }
        if (auto it = o.find("material"); it != o.end()) loadMaterial(*it, path + ".material", obj.material);
        scene_.objects.push_back(std::move(obj));
    }

    void loadGltfObject(const json& o, const std::string& path) {
        GltfModel model;
        if (auto it = o.find("transform"); it != o.end()) {
            const std::string tpath = path + ".transform";
            if (!it->is_object()) return error(tpath, "must be an object {translation, rotation_deg, scale}");
            checkKeys(*it, tpath, {"translation", "rotation_deg", "scale"});
            if (auto t = it->find("translation"); t != it->end()) vec3(*t, tpath + ".translation", kAny, model.transform.translation);
            if (auto r = it->find("rotation_deg"); r != it->end()) vec3(*r, tpath + ".rotation_deg", kAny, model.transform.rotationDeg);
            if (auto sc = it->find("scale"); sc != it->end()) {
                if (sc->is_number()) {
                    double uniform = 1.0;
                    if (number(*sc, tpath + ".scale", kPositive, uniform)) model.transform.scale = {uniform, uniform, uniform};
                } else {
                    vec3(*sc, tpath + ".scale", kPositive, model.transform.scale);
                }
            }
        }
        auto file = o.find("file");
        if (file == o.end() || !file->is_string() || file->get<std::string>().empty())
            return error(path + ".file", "missing; expected a .gltf or .glb path");
        const std::filesystem::path resolved = (baseDir_ / file->get<std::string>()).lexically_normal();
        // What one file may bring, a scene's files may bring together: 256 objects of one file
        // would otherwise each take what that file does.
        const GltfLimits& whole = limits_;
        GltfLimits left = whole;
        left.maxVertices -= sceneVertices_;
        left.maxIndices -= sceneIndices_;
        left.maxImageBytes -= sceneImageBytes_;
        Diagnostics problems;
        std::optional<TriangleMesh> mesh = loadGltf(resolved, model.transform, problems, left);
        if (!mesh) {
            error(path + ".file", "'" + resolved.string() + "' cannot be drawn: " + std::to_string(problems.size()) +
                                      (problems.size() == 1 ? " problem follows" : " problems follow"));
            if ((sceneVertices_ || sceneIndices_ || sceneImageBytes_) && refusedForLimits(problems, left))
                error(path + ".file", "the limits that follow are what the scene's glTF files may hold together (" +
                                          std::to_string(whole.maxVertices) + " vertices, " +
                                          std::to_string(whole.maxIndices) + " indices and " +
                                          std::to_string(whole.maxImageBytes) +
                                          " bytes of decoded images), less what its earlier objects hold");
            for (const Diagnostic& d : problems.items()) diags_.add(d);
            return;
        }
        sceneVertices_ += mesh->vertices.size();
        sceneIndices_ += mesh->indices.size();
        for (const MeshImage& image : mesh->images) sceneImageBytes_ += image.rgba.size();
        model.mesh = std::make_shared<const TriangleMesh>(std::move(*mesh));
        SceneObject obj;
        obj.shape = std::move(model);
        scene_.objects.push_back(std::move(obj));
    }

    void loadMaterial(const json& m, const std::string& path, Material& mat) {
        if (!m.is_object()) return error(path, "must be an object");
        checkKeys(m, path, {"base_color", "metallic", "roughness", "ao"});
        if (auto it = m.find("base_color"); it != m.end()) vec3(*it, path + ".base_color", kUnit, mat.baseColor);
        optionalNumber(m, path, "metallic", kUnit, mat.metallic);
        optionalNumber(m, path, "roughness", kUnit, mat.roughness);
        optionalNumber(m, path, "ao", kUnit, mat.ao);
    }

    std::filesystem::path baseDir_;
    const GltfLimits limits_;
    Scene scene_;
    Diagnostics diags_;
    size_t sceneVertices_ = 0, sceneIndices_ = 0, sceneImageBytes_ = 0;  // of the glTF objects loaded so far
};

}  // namespace

Scene parseScene(std::string_view text, const std::string& fileName, const std::filesystem::path& baseDir,
                 const GltfLimits& limits) {
    return SceneLoader(fileName, baseDir, limits).load(text);
}

Scene loadSceneFile(const std::filesystem::path& path, const GltfLimits& limits) {
    const auto fail = [&](const std::string& message) {
        Diagnostics d;
        d.add({path.string(), "", "", "", message});
        throw SceneError(std::move(d));
    };
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    const int openError = errno;
    std::error_code ec;
    if (!in && openError) fail("cannot open the file: " + std::generic_category().message(openError));
    if (!in || std::filesystem::is_directory(path, ec)) fail("cannot open the file");
    // Up to the limit: a device or a pipe need not end.
    std::string text;
    for (char piece[1 << 14]; in.read(piece, sizeof piece) || in.gcount() > 0;) {
        text.append(piece, size_t(in.gcount()));
        if (text.size() > kMaxSceneFileBytes)
            fail("is larger than " + std::to_string(kMaxSceneFileBytes >> 20) + " MiB, the most a scene file may be");
    }
    if (in.bad()) fail("cannot read the file");
    return parseScene(text, path.string(), std::filesystem::absolute(path, ec).parent_path(), limits);
}

}  // namespace skygraph
