// skygraph_scene: the shipped scenes, every class of error with its JSON path, and the mapping
// from a scene to the features of graphs/raster.json.
#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include "gltf_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace fs = std::filesystem;
using namespace skygraph;

namespace {

const fs::path kScenes = fs::path(SKYGRAPH_SOURCE_DIR) / "scenes";

Scene parse(const std::string& text) { return parseScene(text, "test.json", kScenes); }

/// Parsing `text` throws a SceneError with a diagnostic at `path` whose message contains `what`.
void expectError(const std::string& text, const std::string& path, const std::string& what) {
    SCOPED_TRACE(text);
    try {
        (void)parse(text);
        ADD_FAILURE() << "no error";
    } catch (const SceneError& e) {
        bool found = false;
        for (const Diagnostic& d : e.diagnostics().items()) {
            EXPECT_EQ(d.file, "test.json");
            found |= d.jsonPath == path && d.message.find(what) != std::string::npos;
        }
        EXPECT_TRUE(found) << "expected '" << what << "' at '" << path << "', got:\n" << e.what();
        EXPECT_EQ(std::string(e.what()).rfind("test.json:", 0), 0u) << e.what();
    }
}

std::string sphereWith(const std::string& material) {
    return R"({"objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": )" + material + "}]}";
}

TEST(SceneFiles, EveryShippedSceneLoads) {
    int count = 0;
    for (const auto& entry : fs::directory_iterator(kScenes)) {
        if (entry.path().extension() != ".json") continue;
        SCOPED_TRACE(entry.path().string());
        ++count;
        EXPECT_NO_THROW((void)loadSceneFile(entry.path()));
    }
    EXPECT_GE(count, 4);
}

/// The five features of graphs/raster.json that a scene decides.
FeatureValues rasterFeatures(bool geometry, bool skybox, bool file, bool cubemap, bool sequence = false) {
    return {{"geometry", geometry},  {"skybox", skybox}, {"environment_file", file}, {"sample_cubemap", cubemap},
            {"environment_sequence", sequence}};
}

TEST(SceneFiles, ShippedScenesDecideTheRasterFeatures) {
    const Scene def = loadSceneFile(kScenes / "default.json");
    EXPECT_EQ(def.objects.size(), 7u);
    ASSERT_TRUE(def.environment);
    EXPECT_TRUE(def.environment->procedural);
    EXPECT_EQ(sceneFeatures(def), rasterFeatures(true, true, false, false));
    EXPECT_EQ(effectiveTonemapper(def), Tonemapper::AcesNarkowicz);

    const Scene sky = loadSceneFile(kScenes / "sky_only.json");
    EXPECT_EQ(sceneFeatures(sky), rasterFeatures(false, true, false, false));
    EXPECT_EQ(sky.environment->sampling, EnvironmentSampling::Equirect);

    const Scene studio = loadSceneFile(kScenes / "studio.json");
    ASSERT_TRUE(studio.environment);
    EXPECT_FALSE(studio.environment->procedural);
    EXPECT_EQ(studio.environment->file, "/usr/share/blender/datafiles/studiolights/world/studio.exr");
    EXPECT_EQ(sceneFeatures(studio), rasterFeatures(true, true, true, studio.environment->sampling == EnvironmentSampling::Cubemap));

    const Scene empty = loadSceneFile(kScenes / "empty.json");
    EXPECT_FALSE(empty.environment);
    EXPECT_EQ(sceneFeatures(empty), rasterFeatures(false, false, false, false));
    EXPECT_EQ(explainSceneFeatures(empty),
              (std::vector<std::string>{"geometry = off: the scene has no objects (no forward pass, no depth)",
                                        "skybox = off: the scene has no environment (no skybox, no IBL)"}));
}

// What one glTF file may bring, a scene's files may bring together: objects of one file each
// flatten it again, so a small file drawn 256 times would take 256 times what it does. The box has
// 24 vertices and 36 indices; a budget of 60 vertices holds two of them, not three.
TEST(SceneFiles, TheGltfLimitsHoldForTheSceneFilesTogether) {
    const std::string box = (gltf_test::kModels / "BoxTextured-glTF/BoxTextured.gltf").string();
    std::string text = R"({"objects": [)";
    for (int i = 0; i < 3; ++i) text += std::string(i ? ", " : "") + R"({"type": "gltf", "file": ")" + box + R"("})";
    text += "]}";
    GltfLimits limits;
    limits.maxVertices = 60;
    EXPECT_EQ(parseScene(text, "test.json", kScenes, {}).objects.size(), 3u) << "the default limits hold three";
    try {
        (void)parseScene(text, "test.json", kScenes, limits);
        ADD_FAILURE() << "loaded";
    } catch (const SceneError& e) {
        const auto& d = e.diagnostics().items();
        ASSERT_GE(d.size(), 3u) << e.what();
        EXPECT_EQ(d[0].jsonPath, "objects[2].file") << e.what();
        EXPECT_NE(d[1].message.find("what the scene's glTF files may hold together (60 vertices"), std::string::npos)
            << e.what();
        EXPECT_NE(d[2].message.find("the file has more than 12 vertices"), std::string::npos) << e.what();
    }
    // A file refused for another reason after the first is not said to be past the limits.
    const std::string missing = R"({"objects": [{"type": "gltf", "file": ")" + box +
                                R"("}, {"type": "gltf", "file": "absent.gltf"}]})";
    try {
        (void)parseScene(missing, "test.json", kScenes, limits);
        ADD_FAILURE() << "loaded";
    } catch (const SceneError& e) {
        EXPECT_EQ(std::string(e.what()).find("may hold together"), std::string::npos) << e.what();
    }
}

// Past the object limit the scene is refused before any object loads: each glTF object decodes
// its file, so thousands of them took gigabytes before the count was refused. The glTF files
// here do not exist; none is opened, so the count is the only error.
TEST(SceneFiles, MoreObjectsThanTheLimitAreRefusedBeforeAnyLoads) {
    const auto objects = [](size_t n) {
        std::string text = R"({"objects": [)";
        for (size_t i = 0; i < n; ++i) text += std::string(i ? ", " : "") + R"({"type": "gltf", "file": "none.glb"})";
        return text + "]}";
    };
    try {
        (void)parse(objects(kMaxSceneObjects + 1));
        ADD_FAILURE() << "loaded";
    } catch (const SceneError& e) {
        ASSERT_EQ(e.diagnostics().size(), 1u) << e.what();
        EXPECT_EQ(e.diagnostics().items()[0].jsonPath, "objects");
        EXPECT_EQ(e.diagnostics().items()[0].message, "has 257 objects; at most 256 are allowed");
    }
    // At the limit, each object is tried.
    try {
        (void)parse(objects(kMaxSceneObjects));
        ADD_FAILURE() << "loaded";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("test.json: objects[255].file: '"), std::string::npos);
    }
}

// A scene file past the limit, or a device that never ends, is refused with the file named,
// having read no more than the limit.
TEST(SceneFiles, AFileLargerThanTheLimitIsRefused) {
    for (const std::filesystem::path& file : {std::filesystem::path("/dev/zero"),
                                             std::filesystem::temp_directory_path() / "skygraph-large-scene.json"}) {
        if (file.filename() != "zero") {
            std::ofstream out(file, std::ios::binary);
            out << "{\"objects\": []}" << std::string(kMaxSceneFileBytes, ' ');
        }
        try {
            (void)loadSceneFile(file);
            ADD_FAILURE() << file << " loaded";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(file.string() + ": is larger than 16 MiB, the most a scene file may be"),
                      std::string::npos)
                << e.what();
        }
        if (file.filename() != "zero") std::filesystem::remove(file);
    }
}

TEST(SceneFeatures, DebugViewForcesPassthroughAndKeepsFeatures) {
    Scene s = parse(R"({"tonemapper": "aces_hill", "debug_view": "roughness",
                        "environment": {"file": "procedural"}})");
    EXPECT_EQ(s.tonemapper, Tonemapper::AcesHill);
    EXPECT_EQ(effectiveTonemapper(s), Tonemapper::Passthrough);
    EXPECT_EQ(sceneFeatures(s), rasterFeatures(false, true, false, false));
    s.debugView = DebugView::None;
    EXPECT_EQ(effectiveTonemapper(s), Tonemapper::AcesHill);
    EXPECT_EQ(toString(effectiveTonemapper(parse(R"({"debug_view": "ao"})"))), "passthrough");
}

TEST(SceneLoader, EmptyObjectGivesTheDocumentedDefaults) {
    const Scene s = parse("{}");
    EXPECT_EQ(s.camera.fovYDeg, 60.0);
    EXPECT_EQ(s.camera.near, 0.1);
    EXPECT_FALSE(s.environment);
    EXPECT_EQ(s.tonemapper, Tonemapper::AcesNarkowicz);
    EXPECT_EQ(s.debugView, DebugView::None);
    EXPECT_EQ(sceneFeatures(s), rasterFeatures(false, false, false, false));
    const Scene m = parse(R"({"objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 3, 4]}]})");
    const auto& plane = std::get<Plane>(m.objects.at(0).shape);
    EXPECT_DOUBLE_EQ(plane.normal[1], 0.6);
    EXPECT_DOUBLE_EQ(plane.normal[2], 0.8);
    EXPECT_FALSE(plane.halfExtent);
    EXPECT_EQ(m.objects[0].material.roughness, 0.5);
}

TEST(SceneLoader, CameraFarFromTheOriginIsAccepted) {
    const Scene s = parse(R"({"camera": {"position": [1e7, 0, -1e7], "near": 1e-5}})");
    EXPECT_EQ(s.camera.position[0], 1e7);
    EXPECT_EQ(s.camera.near, 1e-5);
}

TEST(SceneLoader, CameraForwardFollowsTheDocumentedConvention) {
    auto near3 = [](Vec3 a, Vec3 b) {
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], 1e-12);
    };
    near3(cameraForward({}), {0, 0, -1});
    near3(cameraForward({.yawDeg = 90}), {-1, 0, 0});  // yaw turns left
    near3(cameraForward({.pitchDeg = 90}), {0, 1, 0});  // pitch looks up
    near3(cameraForward({.rollDeg = 45}), {0, 0, -1});
}

TEST(SceneLoader, RelativeEnvironmentFilesResolveAgainstTheSceneFolder) {
    const fs::path dir = fs::temp_directory_path() / "skygraph_scene_test_rel";
    fs::create_directories(dir / "env");
    std::ofstream(dir / "env" / "sky.HDR") << "not read by the scene loader";
    std::ofstream(dir / "s.json") << R"({"environment": {"file": "env/../env/sky.HDR", "rotation_deg": -45}})";
    const Scene s = loadSceneFile(dir / "s.json");
    EXPECT_EQ(s.environment->file, fs::absolute(dir / "env" / "sky.HDR"));
    EXPECT_EQ(s.environment->rotationDeg, -45.0);
    EXPECT_EQ(s.environment->sampling, EnvironmentSampling::Cubemap);
    fs::remove_all(dir);
}

TEST(SceneLoader, TheSunDirectionIsNormalisedAndOnlyForTheProceduralSky) {
    const Scene s = parse(R"({"environment": {"file": "procedural", "sun_direction": [0, 2, 0]}})");
    EXPECT_EQ(s.environment->sunDirection, (Vec3{0.0, 1.0, 0.0}));
    const Scene d = parse(R"({"environment": {"file": "procedural"}})");
    const auto def = math::proceduralSunDirection<double>();
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(d.environment->sunDirection[size_t(i)], def[i], 1e-12) << "the shaders' default";
    expectError(R"({"environment": {"file": "procedural", "sun_direction": [0, 0, 0]}})", "environment.sun_direction",
                "must not be the zero vector");
    // Any length a float holds: 1e-20 a component squares below a double's range.
    const Scene tiny = parse(R"({"environment": {"file": "procedural", "sun_direction": [1e-20, 1e-20, 1e-20]}})");
    for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(tiny.environment->sunDirection[i], 1.0 / std::sqrt(3.0), 1e-15);
    const Scene huge = parse(R"({"environment": {"file": "procedural", "sun_direction": [3e38, 0, 3.2e38]}})");
    EXPECT_NEAR(huge.environment->sunDirection[0], 3.0 / std::hypot(3.0, 3.2), 1e-15);
    EXPECT_NEAR(huge.environment->sunDirection[2], 3.2 / std::hypot(3.0, 3.2), 1e-15);
    expectError(R"({"environment": {"file": "sky.hdr", "sun_direction": [0, 1, 0]}})", "environment.sun_direction",
                "only the procedural sky has a sun");
}

// A scene may name files whose names hold control characters (Linux allows any byte but '/'):
// they load, and the lines `skygraph render` prints about them show those characters escaped.
TEST(SceneLoader, FilesNamedWithControlCharactersAreExplainedEscaped) {
    const fs::path dir = fs::temp_directory_path() / "skygraph_scene_test_names";
    fs::remove_all(dir);
    fs::create_directories(dir / "frames\n");
    std::ofstream(dir / "sky\a.hdr") << "x";
    for (const char* frame : {"sky_000.exr", "sky_001.exr"}) std::ofstream(dir / "frames\n" / frame) << "x";
    std::ofstream(dir / "file.json") << R"({"environment": {"file": "sky\u0007.hdr"}})";
    std::ofstream(dir / "sequence.json") << R"({"environment": {"sequence": "frames\n/sky_%03d.exr"}})";
    const Scene file = loadSceneFile(dir / "file.json");
    ASSERT_TRUE(file.environment);
    EXPECT_EQ(file.environment->file, dir / "sky\a.hdr") << "the file as it is named";
    const Scene sequence = loadSceneFile(dir / "sequence.json");
    ASSERT_TRUE(sequence.environment && sequence.environment->sequence);
    EXPECT_EQ(sequence.environment->sequence->count, 2u);
    std::string all;
    for (const Scene* s : {&file, &sequence})
        for (const std::string& line : explainSceneFeatures(*s)) all += line + "\n";
    EXPECT_NE(all.find("environment is '" + dir.string() + "/sky\\u0007.hdr'"), std::string::npos) << all;
    EXPECT_NE(all.find("environment is '" + dir.string() + "/frames\\u000a/sky_000.exr'"), std::string::npos) << all;
    EXPECT_NE(all.find("'" + dir.string() + "/frames\\u000a/sky_%03d.exr'"), std::string::npos) << all;
    EXPECT_EQ(std::count_if(all.begin(), all.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }),
              std::count(all.begin(), all.end(), '\n'))
        << all;
    fs::remove_all(dir);
}

TEST(SceneLoader, ASequenceFindsItsFramesFromZeroOrOneWithoutAGap) {
    const fs::path dir = fs::temp_directory_path() / "skygraph_scene_test_sequence";
    fs::remove_all(dir);
    fs::create_directories(dir / "frames");
    for (int i : {1, 2, 3, 5}) std::ofstream(dir / "frames" / ("sky_" + std::string(i < 10 ? "00" : "0") + std::to_string(i) + ".exr")) << "x";
    std::ofstream(dir / "s.json") << R"({"environment": {"sequence": "frames/sky_%03d.exr", "fps": 30}})";
    const Scene s = loadSceneFile(dir / "s.json");
    ASSERT_TRUE(s.environment && s.environment->sequence);
    const EnvironmentSequence& q = *s.environment->sequence;
    EXPECT_EQ(q.first, 1u) << "no frame 0";
    EXPECT_EQ(q.count, 3u) << "frame 4 is missing: 5 is not part of it";
    EXPECT_EQ(q.fps, 30.0);
    EXPECT_EQ(q.frame(2), fs::absolute(dir / "frames" / "sky_003.exr"));
    EXPECT_FALSE(s.environment->procedural);
    EXPECT_EQ(s.environment->file, q.frame(0)) << "the first frame stands for the environment";
    EXPECT_EQ(sceneFeatures(s), rasterFeatures(false, true, true, true, true));
    EXPECT_EQ(explainSceneFeatures(s).back(), "environment_sequence = on: the environment is a sequence of 3 frames at "
                                              "30.000000 fps, '" + q.pattern + "'");

    std::ofstream(dir / "frames" / "sky_000.exr") << "x";
    std::ofstream(dir / "t.json") << R"({"environment": {"sequence": "frames/sky_%03d.exr"}})";
    const Scene t = loadSceneFile(dir / "t.json");
    EXPECT_EQ(t.environment->sequence->first, 0u);
    EXPECT_EQ(t.environment->sequence->count, 4u);
    EXPECT_EQ(t.environment->sequence->fps, 24.0) << "the default";
    fs::remove(dir / "frames" / "sky_001.exr");
    const Scene still = loadSceneFile(dir / "t.json");
    EXPECT_EQ(still.environment->sequence->count, 1u);
    EXPECT_EQ(sceneFeatures(still).at("environment_sequence"), false) << "one frame is a still";
    fs::remove_all(dir);
}

TEST(SceneLoader, SequencePatternsHoldOneNumber) {
    EXPECT_EQ(formatSequenceFrame("a/%d.exr", 12), "a/12.exr");
    EXPECT_EQ(formatSequenceFrame("a/%04d.exr", 12), "a/0012.exr");
    EXPECT_EQ(formatSequenceFrame("a/%02d.exr", 123), "a/123.exr") << "a width is a minimum";
    EXPECT_EQ(sequenceFrameFile("/a/100%/f_%03d.exr", 7), std::filesystem::path("/a/100%/f_007.exr"))
        << "a folder's '%' is left alone";
    EXPECT_EQ(sequencePatternProblem("f_%05d_x.hdr"), "");
    for (const char* bad : {"f.exr", "f_%s.exr", "f_%5d.exr", "f_%00d.exr", "f_%d_%d.exr", "f_%d%%.exr", "f_%"})
        EXPECT_NE(sequencePatternProblem(bad), "") << bad;
}

// A folder named like a frame would end the sequence there, or start it at frame 1, without a
// word: it is refused, named.
TEST(SceneLoader, AFolderNamedLikeASequenceFrameIsRefused) {
    const fs::path dir = fs::temp_directory_path() / "skygraph_scene_test_sequence_folder";
    fs::remove_all(dir);
    fs::create_directories(dir / "frames");
    for (int i : {0, 1, 3}) std::ofstream(dir / "frames" / ("sky_00" + std::to_string(i) + ".exr")) << "x";
    fs::create_directories(dir / "frames" / "sky_002.exr");
    std::ofstream(dir / "s.json") << R"({"environment": {"sequence": "frames/sky_%03d.exr"}})";
    const auto expectRefused = [&](const std::string& frame) {
        try {
            (void)loadSceneFile(dir / "s.json");
            ADD_FAILURE() << "no error";
        } catch (const SceneError& e) {
            ASSERT_EQ(e.diagnostics().size(), 1u) << e.what();
            EXPECT_EQ(e.diagnostics().items()[0].jsonPath, "environment.sequence");
            EXPECT_NE(e.diagnostics().items()[0].message.find(
                          "'" + (dir / "frames" / frame).string() + "' is named like a frame but is a folder"),
                      std::string::npos)
                << e.what();
        }
    };
    expectRefused("sky_002.exr");  // it would have ended the sequence after two frames
    fs::remove_all(dir / "frames");
    fs::create_directories(dir / "frames" / "sky_000.exr");
    std::ofstream(dir / "frames" / "sky_001.exr") << "x";
    expectRefused("sky_000.exr");  // it would have started the sequence at frame 1
    fs::remove(dir / "frames" / "sky_001.exr");
    expectRefused("sky_000.exr");  // not "no first frame"
    fs::remove_all(dir);
}

TEST(SceneErrors, Sequences) {
    expectError(R"({"environment": {"sequence": "frames/%04d.png"}})", "environment.sequence", "neither .hdr nor .exr");
    expectError(R"({"environment": {"sequence": "frames/0001.exr"}})", "environment.sequence",
                "'frames/0001.exr': its file name must hold the frame number");
    expectError(R"({"environment": {"sequence": "f%d/sky.exr"}})", "environment.sequence", "its file name must hold");
    expectError(R"({"environment": {"sequence": 4}})", "environment.sequence", "must be a file pattern");
    expectError(R"({"environment": {"sequence": "nothing_here/%04d.exr"}})", "environment.sequence",
                "no first frame: neither '" + (kScenes / "nothing_here/0000.exr").string() + "' nor '" +
                    (kScenes / "nothing_here/0001.exr").string() + "' exists");
    expectError(R"({"environment": {"sequence": "f/%d.exr", "file": "sky.hdr"}})", "environment.file", "not both");
    expectError(R"({"environment": {"sequence": "f/%d.exr", "fps": 0}})", "environment.fps", "must be in (0, 1000]");
    expectError(R"({"environment": {"file": "procedural", "fps": 24}})", "environment.fps", "only a sequence");
    expectError(R"({"environment": {"sequence": "f/%d.exr", "sun_direction": [0, 1, 0]}})",
                "environment.sun_direction", "only the procedural sky has a sun");
}

TEST(SceneErrors, FileAndSyntax) {
    try {
        (void)loadSceneFile(kScenes / "no_such_scene.json");
        ADD_FAILURE();
    } catch (const GraphError& e) {  // SceneError is a GraphError: the CLI reports both alike
        EXPECT_NE(std::string(e.what()).find("no_such_scene.json: cannot open the file"), std::string::npos);
    }
    try {
        (void)parse("{\n  \"camera\": {\"near\": 0.1,}\n}");
        ADD_FAILURE();
    } catch (const SceneError& e) {
        ASSERT_EQ(e.diagnostics().size(), 1u);
        EXPECT_EQ(e.diagnostics().items()[0].line, 2);
        EXPECT_GT(e.diagnostics().items()[0].column, 0);
    }
    expectError("[1, 2]", "", "must be a JSON object");
    expectError(R"({"exposure_ev": 1, "exposure_ev": 2})", "exposure_ev", "duplicate key");
}

TEST(SceneErrors, UnknownKeysAtEveryLevel) {
    expectError(R"({"camra": {}})", "camra", "unknown key 'camra'");
    expectError(R"({"camera": {"fov": 60}})", "camera.fov", "expected one of: position");
    expectError(R"({"environment": {"file": "procedural", "intensity": 2}})", "environment.intensity",
                "unknown key");
    expectError(R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": 1, "normal": [0,1,0]}]})",
                "objects[0].normal", "unknown key");
    expectError(sphereWith(R"({"albedo": [1, 1, 1]})"), "objects[0].material.albedo", "unknown key");
}

TEST(SceneErrors, TypesAndFiniteNumbers) {
    expectError(R"({"exposure_ev": "bright"})", "exposure_ev", "expected a number");
    expectError(R"({"exposure_ev": true})", "exposure_ev", "expected a number");
    // JSON has no inf or NaN; numbers too large for a double are refused by the parser, with
    // line and column (the loader's own finiteness check is a second line of defence).
    // The path names the number itself; other malformed JSON names the object it breaks off in.
    expectError(R"({"camera": {"yaw_deg": 1e400}})", "camera.yaw_deg", "number overflow parsing '1e400'");
    expectError(R"({"camera": {"position": [0, -1e999, 0]}})", "camera.position[1]", "number overflow");
    expectError(R"({"camera": {"yaw_deg": NaN}})", "camera", "malformed JSON");
    // A double the GPU's 32-bit floats cannot hold: infinite there, or a denormal near plane.
    expectError(R"({"camera": {"pitch_deg": 1e39}})", "camera.pitch_deg", "a 32-bit float holds");
    expectError(R"({"camera": {"near": 1e-39}})", "camera.near", "a 32-bit float holds");
    expectError(R"({"objects": [{"type": "sphere", "center": [1e39, 0, 0], "radius": 1}]})", "objects[0].center[0]",
                "a 32-bit float holds");
    expectError(R"({"camera": {"position": [0, 0]}})", "camera.position", "array of 3 numbers");
    expectError(R"({"camera": []})", "camera", "must be an object");
    expectError(R"({"description": 3})", "description", "must be a string");
}

TEST(SceneErrors, RangesAreChecked) {
    expectError(R"({"camera": {"fov_y_deg": 0}})", "camera.fov_y_deg", "must be in [0.001, 180)");
    expectError(R"({"camera": {"fov_y_deg": 180}})", "camera.fov_y_deg", "must be in [0.001, 180)");
    expectError(R"({"camera": {"fov_y_deg": 0.0009}})", "camera.fov_y_deg", "must be in [0.001, 180)");
    EXPECT_EQ(parse(R"({"camera": {"fov_y_deg": 0.001}})").camera.fovYDeg, 0.001);
    expectError(R"({"camera": {"near": 0}})", "camera.near", "must be > 0");
    expectError(R"({"camera": {"near": -1}})", "camera.near", "must be > 0");
    // Depth is near / distance: 2e-38 put geometry 1.7 units away below a float's smallest
    // normal, flushed to the sky's depth.
    expectError(R"({"camera": {"near": 2e-38}})", "camera.near",
                "must be at least 1e-6: depth is near / distance, and a nearer plane leaves distant geometry below a "
                "float's smallest normal, where it vanishes; got 2e-38");
    expectError(R"({"camera": {"near": 9.9e-7}})", "camera.near", "must be at least 1e-6");
    EXPECT_EQ(parse(R"({"camera": {"near": 1e-6}})").camera.near, 1e-6);
    expectError(R"({"exposure_ev": 100})", "exposure_ev", "must be in [-64, 64]");
    expectError(sphereWith(R"({"roughness": 1.5})"), "objects[0].material.roughness", "must be in [0, 1]");
    expectError(sphereWith(R"({"metallic": -0.1})"), "objects[0].material.metallic", "must be in [0, 1]");
    expectError(sphereWith(R"({"ao": 2})"), "objects[0].material.ao", "must be in [0, 1]");
    expectError(sphereWith(R"({"base_color": [0.5, 1.2, 0]})"), "objects[0].material.base_color[1]",
                "must be in [0, 1]");
    expectError(R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": 0}]})", "objects[0].radius",
                "must be > 0");
    expectError(R"({"objects": [{"type": "plane", "point": [0,0,0], "normal": [0,1,0], "half_extent": -2}]})",
                "objects[0].half_extent", "must be > 0");
    expectError(R"({"objects": [{"type": "plane", "point": [0,0,0], "normal": [0,0,0]}]})", "objects[0].normal",
                "zero vector");
}

TEST(SceneErrors, EnumerationsNameTheChoices) {
    expectError(R"({"tonemapper": "reinhard"})", "tonemapper", "expected one of aces_hill, aces_narkowicz");
    expectError(R"({"debug_view": "albedo"})", "debug_view", "ao, metallic, none, normal, roughness");
    expectError(R"({"environment": {"file": "procedural", "sampling": "octahedral"}})", "environment.sampling",
                "expected one of cubemap, equirect");
}

TEST(SceneErrors, Environment) {
    expectError(R"({"environment": "procedural"})", "environment", "must be an object");
    expectError(R"({"environment": {"rotation_deg": 0}})", "environment.file", "missing");
    expectError(R"({"environment": {"file": 5}})", "environment.file", "not a file name");
    expectError(R"({"environment": {"file": "sky.png"}})", "environment.file", "neither");
    expectError(R"({"environment": {"file": "missing_sky.exr"}})", "environment.file",
                (kScenes / "missing_sky.exr").string() + "' does not exist");
}

TEST(SceneErrors, Objects) {
    expectError(R"({"objects": {}})", "objects", "must be an array");
    expectError(R"({"objects": [3]})", "objects[0]", "must be an object");
    expectError(R"({"objects": [{"center": [0,0,0]}]})", "objects[0].type", "expected \"sphere\", \"plane\" or \"gltf\"");
    expectError(R"({"objects": [{"type": "cube"}]})", "objects[0].type", "got \"cube\"");
    expectError(R"({"objects": [{"type": "sphere", "radius": 1}]})", "objects[0].center", "missing");
    expectError(R"({"objects": [{"type": "sphere", "center": [0,0,0]}]})", "objects[0].radius", "missing");
    expectError(R"({"objects": [{"type": "plane", "point": [0,0,0]}]})", "objects[0].normal", "missing");
    std::string many = R"({"objects": [)";
    for (size_t i = 0; i <= kMaxSceneObjects; ++i)
        many += std::string(i ? "," : "") + R"({"type": "sphere", "center": [0,0,0], "radius": 1})";
    expectError(many + "]}", "objects", "at most 256");
}

TEST(SceneErrors, AllProblemsAreReportedAtOnce) {
    try {
        (void)parse(R"({"camera": {"fov_y_deg": 200, "near": 0},
                        "tonemapper": "x",
                        "objects": [{"type": "sphere", "center": [0,0,0], "radius": -1,
                                     "material": {"roughness": 3}}]})");
        ADD_FAILURE();
    } catch (const SceneError& e) {
        std::vector<std::string> paths;
        for (const auto& d : e.diagnostics().items()) paths.push_back(d.jsonPath);
        EXPECT_EQ(paths, (std::vector<std::string>{"camera.fov_y_deg", "camera.near", "tonemapper",
                                                   "objects[0].radius", "objects[0].material.roughness"}));
    }
}

}  // namespace
