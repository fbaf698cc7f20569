// Scene files (scenes/*.json, schema schemas/scene.schema.json): the camera, the environment,
// exposure and tonemapping, a debug view, and objects: analytic spheres and planes, and glTF
// files. The scene also decides which features of graphs/raster.json are on (see
// sceneFeatures()).
//
// Units: positions in world units (Y up), angles in degrees. The camera uses reverse-Z with an
// infinite far plane, so only `near` bounds depth.
#pragma once

#include <skygraph/condition.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/triangle_mesh.hpp>

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace skygraph {

/// Most objects a scene may hold; the forward pass may size its buffers by it.
inline constexpr size_t kMaxSceneObjects = 256;
/// Largest scene file loadSceneFile() reads (a scene of kMaxSceneObjects takes a few KiB).
inline constexpr uint64_t kMaxSceneFileBytes = 16ull << 20;

using Vec3 = std::array<double, 3>;

/// yaw 0, pitch 0 looks down -Z; yaw turns left about +Y, pitch up about the camera's X,
/// roll about its view direction (counter-clockwise as seen by the camera).
struct SceneCamera {
    Vec3 position{0.0, 1.0, 5.0};
    double yawDeg = 0.0;
    double pitchDeg = 0.0;
    double rollDeg = 0.0;
    double fovYDeg = 60.0;  ///< vertical field of view, in (0, 180)
    double near = 0.1;      ///< > 0; the far plane is at infinity (reverse-Z)
};

enum class EnvironmentSampling { Cubemap, Equirect };

/// Equirect frames played as an animated sky, one file a frame, named by a pattern whose file
/// name holds one printf-style number: `%d`, or `%0Nd` for N digits with leading zeros (N
/// from 1 to 9).
/// The frames are numbered from 0 or 1 on, without a gap; playback loops.
struct EnvironmentSequence {
    std::string pattern;  ///< absolute (resolved against the scene's folder), e.g. /x/frames/%04d.exr
    double fps = 24.0;    ///< in (0, 1000]
    uint32_t first = 0;   ///< the first frame's number: 0 or 1, whichever file exists
    uint32_t count = 0;   ///< the frames found from `first` on, at least 1
    /// The file of the sequence's frame `index` (0 <= index < count): number first + index.
    [[nodiscard]] std::filesystem::path frame(uint32_t index) const;
    [[nodiscard]] bool operator==(const EnvironmentSequence&) const = default;
};

/// Most frames one sequence may have.
inline constexpr uint32_t kMaxSequenceFrames = 1000000;

/// What is wrong with `pattern` as an EnvironmentSequence pattern, or empty when nothing is.
[[nodiscard]] std::string sequencePatternProblem(std::string_view pattern);
/// `pattern` (sequencePatternProblem() is empty) with its number replaced by `number`.
[[nodiscard]] std::string formatSequenceFrame(std::string_view pattern, uint32_t number);
/// The file of frame `number` of a sequence `pattern` (a path): the number goes into the file
/// name only, so that a folder may hold a '%'.
[[nodiscard]] std::filesystem::path sequenceFrameFile(const std::filesystem::path& pattern, uint32_t number);

struct SceneEnvironment {
    bool procedural = true;      ///< the built-in analytic sky; `file` is empty then
    std::filesystem::path file;  ///< .hdr or .exr, absolute (resolved against the scene's folder);
                                 ///< a sequence's first frame
    double rotationDeg = 0.0;    ///< about +Y
    EnvironmentSampling sampling = EnvironmentSampling::Cubemap;
    /// The procedural sky's sun: a unit vector towards it (math::proceduralSunDirection by
    /// default). A change re-bakes the sky's lighting. Unused for a file.
    Vec3 sunDirection{0.35045588917675863, 0.45058614322726115, -0.8210680832141203};  // (0.35, 0.45, -0.82), normalised
    std::optional<EnvironmentSequence> sequence;  ///< an animated sky, or nullopt
};

/// Per frame, set through Renderer::frameData(): how far the sky has faded from a sequence's
/// previous frame to the current one, for a SkyboxPass with a `previous` environment (0 shows
/// the previous frame, 1 the current). Without it the sky is the current frame.
struct SkyFade {
    double current = 1.0;  ///< in [0, 1]
};

enum class Tonemapper { AcesNarkowicz, AcesHill, KhronosPbrNeutral, Passthrough };
enum class DebugView { None, Normal, Metallic, Roughness, Ao };

struct Material {
    std::array<double, 3> baseColor{0.8, 0.8, 0.8};  ///< linear, each in [0, 1]
    double metallic = 0.0;                           ///< [0, 1]
    double roughness = 0.5;                          ///< [0, 1]
    double ao = 1.0;                                 ///< [0, 1]
};

struct Sphere {
    Vec3 center{0.0, 0.0, 0.0};
    double radius = 1.0;  ///< > 0
};

/// An infinite plane, or a square of side 2 * halfExtent centred on `point` when given.
struct Plane {
    Vec3 point{0.0, 0.0, 0.0};
    Vec3 normal{0.0, 1.0, 0.0};  ///< unit length (the loader normalises it)
    std::optional<double> halfExtent;  ///< > 0
};

/// A glTF 2.0 file's default scene, flattened to world space (loadGltf()). Its primitives
/// carry their own materials; the object's `material` is not used.
struct GltfModel {
    std::shared_ptr<const TriangleMesh> mesh;  ///< never null in a loaded scene
    MeshTransform transform;
};

struct SceneObject {
    std::variant<Sphere, Plane, GltfModel> shape;
    Material material;
};

struct Scene {
    std::string file;                              ///< where it was loaded from, for messages
    SceneCamera camera;
    std::optional<SceneEnvironment> environment;  ///< nullopt: no environment at all
    double exposureEv = 0.0;                       ///< the HDR image is scaled by 2^exposureEv
    Tonemapper tonemapper = Tonemapper::AcesNarkowicz;
    DebugView debugView = DebugView::None;
    std::vector<SceneObject> objects;
};

/// Thrown by the scene loader; a GraphError, so command-line tools report it the same way.
/// Holds every problem in the file, each naming the file and the JSON path.
class SceneError : public GraphError {
public:
    using GraphError::GraphError;
};

/// Reads and validates the scene at `path`; returns a Scene the caller owns. Relative
/// environment files are resolved against the scene file's folder and must exist.
/// Throws SceneError listing all problems: unreadable file, malformed JSON, duplicate or
/// unknown keys, wrong types, non-finite numbers, values out of range, and every problem of
/// its glTF files (each naming that file and its JSON path: loadGltf()). Relative glTF files
/// are resolved like environment files. `limits` hold for all of its glTF files together:
/// what one file may bring, a scene's files may bring between them.
[[nodiscard]] Scene loadSceneFile(const std::filesystem::path& path, const GltfLimits& limits = {});

/// As loadSceneFile() for text in memory (read during the call only). `fileName` is used in
/// messages; relative environment files are resolved against `baseDir`.
[[nodiscard]] Scene parseScene(std::string_view text, const std::string& fileName,
                               const std::filesystem::path& baseDir, const GltfLimits& limits = {});

/// The features of graphs/raster.json that the scene decides:
///   geometry = the scene has objects   (off: the forward pass and depth are culled)
///   skybox   = the scene has an environment (off: no skybox and no IBL work)
///   environment_file = the environment is a file, not the procedural sky
///   sample_cubemap   = a file environment is sampled through a cubemap (else as equirect)
///   environment_sequence = the environment is a sequence of two frames or more
/// A debug view does not change features; it changes the tonemapper (effectiveTonemapper()).
[[nodiscard]] FeatureValues sceneFeatures(const Scene& scene);

/// One line per feature of sceneFeatures() saying why it is on or off, e.g.
/// "geometry = off: the scene has no objects". For `skygraph render` to print: the files it
/// names show control characters escaped, as JSON writes them.
[[nodiscard]] std::vector<std::string> explainSceneFeatures(const Scene& scene);

/// The operator the tonemapping pass must use: Passthrough whenever a debug view is on (the
/// debug values are already in [0, 1]), otherwise the scene's tonemapper.
[[nodiscard]] Tonemapper effectiveTonemapper(const Scene& scene) noexcept;

/// The scene-file spellings: "aces_narkowicz", "cubemap", "normal", ... Returned views point
/// to static storage.
[[nodiscard]] std::string_view toString(Tonemapper t) noexcept;
[[nodiscard]] std::string_view toString(DebugView v) noexcept;
[[nodiscard]] std::string_view toString(EnvironmentSampling s) noexcept;

/// The unit view direction of `camera` in world space, fixing the angle convention above:
/// (-sin yaw cos pitch, sin pitch, -cos yaw cos pitch). Roll does not change it.
[[nodiscard]] Vec3 cameraForward(const SceneCamera& camera) noexcept;

}  // namespace skygraph
