// glTF files through loadGltf() and through scene files: Debian's assimp-testmodels (good and
// bad), and small files written here for what those do not cover. Textures, texture
// coordinates and tangents: gltf_materials_test.cpp.
#include "gltf_test_util.hpp"

#include <skygraph/scene.hpp>
#include <skygraph/triangle_mesh.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include <sys/stat.h>
#include <unistd.h>

namespace skygraph {
namespace {

namespace fs = std::filesystem;
using gltf_test::kModels;
using gltf_test::messages;

struct BadFile {
    std::string file;     ///< under kModels
    std::string path;     ///< the JSON path the first diagnostic names
    std::string message;  ///< part of its message
};

// Names the case in test listings (gtest would print the struct's bytes, padding included).
void PrintTo(const BadFile& b, std::ostream* out) { *out << b.file; }

class BadGltf : public ::testing::TestWithParam<BadFile> {};

TEST_P(BadGltf, IsRefusedNamingTheFileAndThePlace) {
    const BadFile& b = GetParam();
    Diagnostics d;
    const auto mesh = loadGltf(kModels / b.file, {}, d);
    EXPECT_FALSE(mesh) << "nothing is drawn of a file with a problem";
    ASSERT_FALSE(d.empty());
    const Diagnostic& first = d.items().front();
    EXPECT_EQ(first.file, (kModels / b.file).string());
    EXPECT_EQ(first.jsonPath, b.path) << messages(d);
    EXPECT_NE(first.message.find(b.message), std::string::npos) << messages(d);
}

INSTANTIATE_TEST_SUITE_P(
    AssimpTestModels, BadGltf,
    ::testing::Values(
        BadFile{"IndexOutOfRange/IndexOutOfRange.gltf", "accessors[0] (indices of meshes[0].primitives[0])",
                "index 0 is 255, past the primitive's 24 vertices"},
        BadFile{"IndexOutOfRange/AllIndicesOutOfRange.gltf", "accessors[0] (indices of meshes[0].primitives[0])",
                "is 65535, past"},
        BadFile{"wrongTypes/badArray.gltf", "meshes[0].primitives", "must be an array of objects"},
        BadFile{"wrongTypes/badExtension.gltf",
                "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform",
                "an extension must be an object"},
        BadFile{"wrongTypes/badNumber.gltf", "materials[0].normalTexture.scale", "must be a number"},
        BadFile{"wrongTypes/badObject.gltf", "materials[0].pbrMetallicRoughness", "must be an object"},
        BadFile{"wrongTypes/badString.gltf", "scenes[0].name", "must be a string, got number 42"},
        BadFile{"wrongTypes/badUint.gltf", "materials[0].pbrMetallicRoughness.baseColorTexture.index",
                "must be an integer >= 0, got number -1"},
        BadFile{"MissingBin/BoxTextured.gltf", "", "BoxTextured0.bin"},
        BadFile{"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "accessors[2] (POSITION of meshes[0].primitives[0])",
                "element 0 is not finite"},
        BadFile{"BoxBadNormals-glTF-Binary/BoxBadNormals.glb", "accessors[1] (NORMAL of meshes[0].primitives[0])",
                "normal 0 has length 0"},
        BadFile{"RecursiveNodes/RecursiveNodes.gltf", "nodes[1].children[0]", "node 0 is its own ancestor"},
        BadFile{"SchemaFailures/sceneWrongType.gltf", "scene", "must be an integer >= 0, got string \"hello\""},
        BadFile{"TestNoRootNode/NoScene.gltf", "scenes", "no scene"},
        BadFile{"TestNoRootNode/SceneWithoutNodes.gltf", "scenes[0].nodes", "no nodes"},
        BadFile{"IncorrectVertexArrays/Cube.gltf", "meshes[1].primitives[0]", "35 indices do not make whole triangles"},
        BadFile{"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_01.gltf", "meshes[0].primitives[0].mode",
                "draws points or lines"},
        BadFile{"BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf", "extensionsRequired", "KHR_technique_webgl"},
        // Said before tinygltf fails on the compressed buffers the extension implies.
        BadFile{"draco/2CylinderEngine.gltf", "extensionsRequired",
                "requires extension 'KHR_draco_mesh_compression', which skygraph does not support"},
        BadFile{"BoxTexcoords-glTF/boxTexcoords.gltf",
                "materials[0].pbrMetallicRoughness.metallicRoughnessTexture.texCoord", "TEXCOORD_1 is not supported"},
        BadFile{"issue_3269/texcoord_crash.gltf", "meshes[0].primitives[0]",
                "its material samples textures, but it has no TEXCOORD_0"}),
    [](const ::testing::TestParamInfo<BadFile>& p) {
        std::string n = p.param.file.substr(p.param.file.rfind('/') + 1);
        for (char& c : n)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return n + "_" + std::to_string(p.index);
    });

// tinygltf looks for a uri in the working directory after the model's folder: a file of the
// missing buffer's name there must not stand in for it.
TEST(Gltf, AMissingBufferIsNotTakenFromTheWorkingDirectory) {
    const fs::path dir = fs::temp_directory_path() / ("skygraph_gltf_cwd_" + std::to_string(getpid()));
    fs::create_directories(dir);
    fs::copy_file(kModels / "BoxTextured-glTF/BoxTextured0.bin", dir / "BoxTextured0.bin",
                  fs::copy_options::overwrite_existing);
    const fs::path before = fs::current_path();
    fs::current_path(dir);
    Diagnostics d;
    const auto mesh = loadGltf(kModels / "MissingBin/BoxTextured.gltf", {}, d);
    fs::current_path(before);
    fs::remove_all(dir);
    EXPECT_FALSE(mesh) << "the working directory's BoxTextured0.bin was read";
    ASSERT_FALSE(d.empty());
    EXPECT_NE(d.items().front().message.find("BoxTextured0.bin"), std::string::npos) << messages(d);
    // The model's own folder still finds its files from anywhere.
    fs::current_path(fs::temp_directory_path());
    Diagnostics good;
    const auto box = loadGltf(kModels / "BoxTextured-glTF/BoxTextured.gltf", {}, good);
    fs::current_path(before);
    EXPECT_TRUE(box) << messages(good);
}

TEST(Gltf, TheBoxIsTheSameInEachContainer) {
    Diagnostics d;
    const auto gltf = loadGltf(kModels / "BoxTextured-glTF/BoxTextured.gltf", {}, d);
    const auto glb = loadGltf(kModels / "BoxTextured-glTF-Binary/BoxTextured.glb", {}, d);
    const auto embedded = loadGltf(kModels / "BoxTextured-glTF-Embedded/BoxTextured.gltf", {}, d);
    ASSERT_TRUE(gltf && glb && embedded) << messages(d);
    EXPECT_EQ(gltf->vertices.size(), 24u);
    EXPECT_EQ(gltf->indices.size(), 36u);
    ASSERT_EQ(gltf->primitives.size(), 1u);
    EXPECT_EQ(gltf->primitives[0].material.metallic, 0.0);  // the file's factor
    for (const auto* other : {&*glb, &*embedded}) {
        EXPECT_EQ(other->indices, gltf->indices);
        ASSERT_EQ(other->vertices.size(), gltf->vertices.size());
        const size_t vertexBytes = gltf->vertices.size() * sizeof(MeshVertex);
        EXPECT_EQ(std::memcmp(other->vertices.data(), gltf->vertices.data(), vertexBytes), 0)
            << "positions, normals, UVs and tangents";
        ASSERT_EQ(other->images.size(), 1u);
        EXPECT_EQ(other->images[0].rgba, gltf->images.at(0).rgba) << "a PNG file, a .glb's buffer view, a data URI";
    }
    // The box is a unit cube about the origin: its node's rotation turns it but keeps it there.
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(gltf->boundsMin[size_t(c)], -0.5, 1e-6);
        EXPECT_NEAR(gltf->boundsMax[size_t(c)], 0.5, 1e-6);
    }
}

TEST(Gltf, TheSceneObjectsTransformPlacesTheModel) {
    Diagnostics d;
    MeshTransform t;
    t.translation = {10.0, 0.0, 0.0};
    t.scale = {2.0, 2.0, 2.0};
    const auto moved = loadGltf(kModels / "BoxTextured-glTF/BoxTextured.gltf", t, d);
    ASSERT_TRUE(moved) << messages(d);
    EXPECT_NEAR(moved->boundsMin[0], 9.0, 1e-6);
    EXPECT_NEAR(moved->boundsMax[0], 11.0, 1e-6);
    EXPECT_NEAR(moved->boundsMax[1], 1.0, 1e-6);
    for (const MeshVertex& v : moved->vertices)
        EXPECT_NEAR(std::hypot(v.normal[0], v.normal[1], v.normal[2]), 1.0, 1e-6) << "normals stay unit";
}

// Positions finite in the file that the transforms carry past a float's range are refused,
// as non-finite ones in the file are: drawn, they vanished or turned a path-traced frame black.
TEST(Gltf, PositionsTheTransformsCarryPastAFloatAreRefused) {
    Diagnostics d;
    MeshTransform t;
    t.scale = {1e39, 1e39, 1e39};  // the box spans 1: its corners land at 5e38
    EXPECT_FALSE(loadGltf(kModels / "BoxTextured-glTF/BoxTextured.gltf", t, d));
    ASSERT_EQ(d.size(), 1u) << messages(d);
    EXPECT_NE(d.items()[0].message.find("past the range of a float"), std::string::npos) << messages(d);
    EXPECT_NE(d.items()[0].jsonPath.find("meshes[0].primitives[0]"), std::string::npos) << messages(d);
}

TEST(Gltf, TheEnginesHierarchyAndCamera) {
    Diagnostics d;
    const auto engine = loadGltf(kModels / "2CylinderEngine-glTF-Binary/2CylinderEngine.glb", {}, d);
    ASSERT_TRUE(engine) << messages(d);
    EXPECT_EQ(engine->primitives.size(), 115u);  // 34 primitives of 29 meshes, instanced by 82 nodes
    EXPECT_EQ(engine->indices.size(), 364488u);
    ASSERT_TRUE(engine->camera);
    EXPECT_NEAR(engine->camera->fovYDeg, 0.3143463730812073 * 180.0 / M_PI, 1e-9);
    const auto& f = engine->camera->forward;
    EXPECT_NEAR(std::hypot(f[0], f[1], f[2]), 1.0, 1e-12);
}

TEST(Gltf, StripsAndFansBecomeTriangleLists) {
    Diagnostics d;
    const fs::path dir = kModels / "glTF-Asset-Generator/Mesh_PrimitiveMode";
    const auto list = loadGltf(dir / "Mesh_PrimitiveMode_04.gltf", {}, d);   // triangles
    const auto strip = loadGltf(dir / "Mesh_PrimitiveMode_05.gltf", {}, d);  // strip
    const auto fan = loadGltf(dir / "Mesh_PrimitiveMode_06.gltf", {}, d);    // fan
    ASSERT_TRUE(list && strip && fan) << messages(d);
    // The same square each way: two triangles, facing the same side.
    for (const auto* m : {&*list, &*strip, &*fan}) {
        ASSERT_EQ(m->indices.size(), 6u);
        for (size_t t = 0; t < 6; t += 3) {
            const auto p = [&](size_t k) { return m->vertices[m->indices[t + k]].position; };
            const double ax = p(1)[0] - p(0)[0], ay = p(1)[1] - p(0)[1], bx = p(2)[0] - p(0)[0], by = p(2)[1] - p(0)[1];
            EXPECT_GT(ax * by - ay * bx, 0.0) << "counter-clockwise seen from +Z";
        }
    }
}

/// A file written here: one triangle whose buffer is a data URI, with `accessorCount` and
/// `normals` as asked.
fs::path writeTriangle(const std::string& name, int accessorCount, bool normals) {
    // Three float3 positions (0,0,0) (1,0,0) (0,1,0), base64.
    const std::string positions = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
    std::string json = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
      "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0)";
    json += normals ? R"(, "NORMAL": 0}}]}],)" : R"(}}]}],)";
    json += R"( "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" + std::to_string(accessorCount) +
            R"(, "type": "VEC3"}], "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,)" + positions + R"("}]})";
    const fs::path file = fs::temp_directory_path() / ("skygraph-" + name + ".gltf");
    std::ofstream(file) << json;
    return file;
}

TEST(Gltf, WithoutNormalsTrianglesAreFlat) {
    Diagnostics d;
    const auto mesh = loadGltf(writeTriangle("flat", 3, false), {}, d);
    ASSERT_TRUE(mesh) << messages(d);
    ASSERT_EQ(mesh->vertices.size(), 3u);
    for (const MeshVertex& v : mesh->vertices) {
        EXPECT_FLOAT_EQ(v.normal[2], 1.0f);
        EXPECT_EQ(mesh->primitives[0].material.metallic, 1.0) << "glTF's default material";
    }
}

TEST(Gltf, AnAccessorPastItsBufferViewIsRefused) {
    gltf_test::expectRefusedAt(writeTriangle("overrun", 1000000, false),
                               "accessors[0] (POSITION of meshes[0].primitives[0])", "1000000 elements need");
}

TEST(Gltf, ZeroLengthNormalsAreRefused) {
    Diagnostics d;
    // NORMAL reads the positions: (0, 0, 0) is a zero normal.
    EXPECT_FALSE(loadGltf(writeTriangle("zero-normal", 3, true), {}, d));
    EXPECT_NE(messages(d).find("normal 0 has length 0"), std::string::npos) << messages(d);
}

TEST(Gltf, ACorruptImageIsRefused) {
    // The triangle file with an image that claims to be a PNG and is not.
    fs::path file = writeTriangle("bad-image", 3, false);
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    text.insert(text.rfind('}'), R"(, "images": [{"uri": "data:image/png;base64,iVBORw0KGgoAAAAAAAAAAAAAAAAAAAAA"}])");
    std::ofstream(file) << text;
    Diagnostics d;
    EXPECT_FALSE(loadGltf(file, {}, d)) << "every image's header is read, sampled or not";
    ASSERT_FALSE(d.empty());
    EXPECT_EQ(d.items()[0].jsonPath, "images[0]") << messages(d);
    EXPECT_NE(messages(d).find("images[0]: not an image stb can read"), std::string::npos) << messages(d);
}

TEST(Gltf, AnImageOutsideItsBufferIsRefused) {
    // The triangle file with an image in a buffer view that runs past the 36-byte buffer.
    fs::path file = writeTriangle("image-past-buffer", 3, false);
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const std::string view = R"({"buffer": 0, "byteLength": 36})";
    text.replace(text.find(view), view.size(), view + R"(, {"buffer": 0, "byteOffset": 20, "byteLength": 1000})");
    text.insert(text.rfind('}'), R"(, "images": [{"bufferView": 1, "mimeType": "image/png"}])");
    std::ofstream(file) << text;
    gltf_test::expectRefusedAt(file, "images[0]", "bufferViews[1], lies outside buffer 0 of 36 bytes");
}

// A well-formed sparse accessor is refused for what it is: sparse storage is not supported
// (before, its `indices` object read as a primitive's index accessor number).
TEST(Gltf, ASparseAccessorIsRefusedAsUnsupported) {
    fs::path file = writeTriangle("sparse", 3, false);
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const std::string type = R"("type": "VEC3"})";
    text.replace(text.find(type), type.size(),
                 R"("type": "VEC3", "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5123},
                    "values": {"bufferView": 0}}})");
    std::ofstream(file, std::ios::trunc) << text;
    gltf_test::expectRefusedAt(file, "accessors[0] (POSITION of meshes[0].primitives[0])",
                               "sparse accessors are not supported");
}

// An index accessor that does not exist is named where the primitive names it, as an
// attribute's is (tinygltf's own message says where nothing).
TEST(Gltf, AMissingIndexAccessorIsNamedAtThePrimitive) {
    fs::path file = writeTriangle("missing-indices", 3, false);
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const std::string attributes = R"({"attributes": {"POSITION": 0})";
    text.replace(text.find(attributes), attributes.size(), R"({"indices": 42, "attributes": {"POSITION": 0})");
    std::ofstream(file, std::ios::trunc) << text;
    gltf_test::expectRefusedAt(file, "meshes[0].primitives[0].indices", "accessor 42 does not exist");
}

/// The triangle file with its nodes and scene roots replaced.
fs::path withNodes(const std::string& name, const std::string& nodes, const std::string& roots) {
    const fs::path file = writeTriangle(name, 3, false);
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const std::string oldNodes = R"("nodes": [{"mesh": 0}])", oldRoots = R"("scenes": [{"nodes": [0]}])";
    text.replace(text.find(oldNodes), oldNodes.size(), R"("nodes": )" + nodes);
    text.replace(text.find(oldRoots), oldRoots.size(), R"("scenes": [{"nodes": )" + roots + "}]");
    std::ofstream(file, std::ios::trunc) << text;
    return file;
}

TEST(Gltf, AHierarchyDeeperThanTheStackLoads) {
    // Node 1 -> 2 -> ... -> kDepth -> 0, the triangle's: recursion this deep overflows a stack.
    constexpr int kDepth = 100000;
    std::string nodes = R"([{"mesh": 0})";
    for (int i = 1; i <= kDepth; ++i) nodes += R"(, {"children": [)" + std::to_string(i < kDepth ? i + 1 : 0) + "]}";
    Diagnostics d;
    const auto mesh = loadGltf(withNodes("deep", nodes + "]", "[1]"), {}, d);
    ASSERT_TRUE(mesh) << messages(d);
    EXPECT_EQ(mesh->vertices.size(), 3u);
}

// tinygltf reads JSON by recursion: nesting this deep (in `extras`, which glTF leaves free)
// overflowed the stack. The JSON is read first with the depth limit of every JSON reader here.
TEST(Gltf, JsonNestedDeeperThanTheReadersAllowIsRefused) {
    constexpr int kDepth = 30000;
    const std::string extras = std::string(kDepth, '[') + std::string(kDepth, ']');
    const std::string json = R"({"asset": {"version": "2.0"}, "extras": )" + extras + "}";
    const fs::path text = fs::temp_directory_path() / "skygraph-deep-extras.gltf";
    std::ofstream(text) << json;
    Diagnostics d;
    EXPECT_FALSE(loadGltf(text, {}, d));
    ASSERT_EQ(d.size(), 1u) << messages(d);
    EXPECT_NE(d.items()[0].message.find("nesting deeper than 256 levels"), std::string::npos) << messages(d);
    EXPECT_GT(d.items()[0].line, 0) << "a .gltf's error has its line and column";
    // The same JSON as a .glb's chunk (padded to 4 bytes, as the format asks).
    std::string chunk = json;
    chunk.resize((chunk.size() + 3) / 4 * 4, ' ');
    const auto word = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    const std::string glb = "glTF" + word(2) + word(uint32_t(12 + 8 + chunk.size())) + word(uint32_t(chunk.size())) +
                            "JSON" + chunk;
    const fs::path binary = fs::temp_directory_path() / "skygraph-deep-extras.glb";
    std::ofstream(binary, std::ios::binary) << glb;
    Diagnostics b;
    EXPECT_FALSE(loadGltf(binary, {}, b));
    ASSERT_EQ(b.size(), 1u) << messages(b);
    EXPECT_NE(b.items()[0].message.find("JSON chunk: nesting deeper than 256 levels"), std::string::npos) << messages(b);
}

// A .glb whose container is cut short or wrong says how, where tinygltf says only "Invalid glTF
// binary" (and reads a GLB of version 1 as if it were 2).
TEST(Gltf, ABrokenGlbContainerIsNamed) {
    const std::string good = [] {
        std::ifstream in(kModels / "BoxTextured-glTF-Binary/BoxTextured.glb", std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), {});
    }();
    ASSERT_GT(good.size(), 100u);
    const auto write = [](const std::string& name, const std::string& bytes) {
        const fs::path file = fs::temp_directory_path() / ("skygraph-" + name + ".glb");
        std::ofstream(file, std::ios::binary) << bytes;
        return file;
    };
    std::string version1 = good;
    version1[4] = 1;
    // The file's first `bytes`, with the header's length to match. tinygltf counted the BIN
    // chunk's length without its 8-byte header: a chunk up to 8 bytes short was read past the end.
    const auto cutTo = [&](size_t bytes) {
        std::string cut = good.substr(0, bytes);
        const uint32_t length = uint32_t(bytes);
        std::memcpy(cut.data() + 8, &length, 4);
        return cut;
    };
    ASSERT_EQ(good.size(), 4696u) << "at byte 1412, after a 1392-byte JSON chunk: the BIN chunk's header and 3276 bytes";
    const std::vector<std::pair<fs::path, std::string>> cases{
        {write("glb-cut", good.substr(0, good.size() / 2)), "truncated: its header says " + std::to_string(good.size()) +
                                                                 " bytes, the file has " + std::to_string(good.size() / 2)},
        {write("glb-header-only", good.substr(0, 8)), "truncated: a .glb starts with a 12-byte header"},
        {write("glb-version-1", version1), "GLB version 1; skygraph reads version 2"},
        {write("glb-bin-short", cutTo(good.size() - 8)), "truncated: its BIN chunk says 3276 bytes, and 3268 follow"},
        {write("glb-bin-header-cut", cutTo(1412 + 4)),
         "truncated: 4 bytes follow the JSON chunk, too few for the BIN chunk's 8-byte header"},
    };
    for (const auto& [file, message] : cases) gltf_test::expectRefusedAt(file, "", message);
}

// tinygltf names only the property for these, or reads the value as something else: a node
// matrix of three numbers became the identity, a rotation of three the identity too.
TEST(Gltf, ValuesTheSchemaForbidsAreRefusedAtTheirPath) {
    const auto edited = [](const std::string& name, const std::string& from, const std::string& to) {
        const fs::path file = writeTriangle(name, 3, false);
        std::ifstream in(file);
        std::string text((std::istreambuf_iterator<char>(in)), {});
        EXPECT_NE(text.find(from), std::string::npos) << from;
        text.replace(text.find(from), from.size(), to);
        std::ofstream(file, std::ios::trunc) << text;
        return file;
    };
    const std::string node = R"("nodes": [{"mesh": 0)";
    const struct {
        fs::path file;
        std::string path, message;
    } cases[]{
        {edited("component-type", "5126", "9999"), "accessors[0].componentType",
         "must be BYTE (5120), UNSIGNED_BYTE (5121), SHORT (5122), UNSIGNED_SHORT (5123), UNSIGNED_INT (5125) or "
         "FLOAT (5126), got 9999"},
        {edited("accessor-type", R"("VEC3")", R"("VEC7")"), "accessors[0].type",
         R"(must be "SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3" or "MAT4", got "VEC7")"},
        {edited("byte-stride", R"("byteLength": 36})", R"("byteLength": 36, "byteStride": 3})"),
         "bufferViews[0].byteStride", "must be a multiple of 4 from 4 to 252, got 3"},
        {edited("stride-256", R"("byteLength": 36})", R"("byteLength": 36, "byteStride": 256})"),
         "bufferViews[0].byteStride", "got 256"},
        {edited("matrix-3", node, node + R"(, "matrix": [1, 2, 3])"), "nodes[0].matrix",
         "must be an array of 16 numbers, got 3"},
        {edited("rotation-3", node, node + R"(, "rotation": [0, 0, 1])"), "nodes[0].rotation",
         "must be an array of 4 numbers, got 3"},
        {edited("scale-2", node, node + R"(, "scale": [2, 2])"), "nodes[0].scale", "must be an array of 3 numbers, got 2"},
        {edited("matrix-and-trs", node,
                node + R"(, "translation": [1, 0, 0], "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1])"),
         "nodes[0]", "has both a matrix and rotation, translation or scale"},
        {edited("mode-7", R"("attributes")", R"("mode": 7, "attributes")"), "meshes[0].primitives[0].mode",
         "must be a primitive mode from 0 to 6, got 7"},
        {edited("version-1", R"("version": "2.0")", R"("version": "1.0")"), "asset.version",
         R"(skygraph reads glTF 2.x, got "1.0")"},
        {edited("no-asset", R"("asset": {"version": "2.0"}, )", ""), "asset", "missing"},
        {edited("no-count", R"("count": 3, )", ""), "accessors[0].count", "missing; glTF requires it here"},
        {edited("view-99", R"("bufferView": 0)", R"("bufferView": 99)"), "accessors[0].bufferView",
         "buffer view 99 does not exist"},
        {edited("no-buffer", R"("buffer": 0, )", ""), "bufferViews[0].buffer", "missing; glTF requires it here"},
        {edited("no-uri", R"(, "uri": "data:)", R"(, "extras": "data:)"), "buffers[0].uri",
         "missing; only the first buffer of a .glb may have none"},
        {edited("no-attributes", R"("attributes": {"POSITION": 0})", R"("extras": {"POSITION": 0})"),
         "meshes[0].primitives[0].attributes", "missing; glTF requires it here"},
        {edited("base-color-2", R"("buffers")",
                R"("materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1]}}], "buffers")"),
         "materials[0].pbrMetallicRoughness.baseColorFactor", "must be an array of 4 numbers, got 2"},
    };
    for (const auto& c : cases) gltf_test::expectRefusedAt(c.file, c.path, c.message);
    // The values at the edges of what the schema allows load.
    for (const fs::path& file :
         {edited("stride-4", R"("byteLength": 36})", R"("byteLength": 36, "byteStride": 12})"),
          edited("matrix-16", node, node + R"(, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1])"),
          edited("trs", node, node + R"(, "translation": [1, 0, 0], "rotation": [0, 0, 0, 1], "scale": [1, 1, 1])"),
          edited("mode-4", R"("attributes")", R"("mode": 4, "attributes")")}) {
        Diagnostics d;
        EXPECT_TRUE(loadGltf(file, {}, d)) << file << ": " << messages(d);
    }
}

// A .glb is not read as JSON when its first bytes are not its magic number.
TEST(Gltf, AGlbWithoutItsMagicNumberIsNamed) {
    const fs::path file = fs::temp_directory_path() / "skygraph-no-magic.glb";
    std::ofstream(file, std::ios::binary | std::ios::trunc) << "NOT A GLB, BUT LONG ENOUGH TO HAVE A HEADER";
    gltf_test::expectRefusedAt(file, "", "is not a binary glTF: a .glb starts with the bytes 'glTF'");
}

TEST(Gltf, AnEmptyFileIsSaidToBeEmpty) {
    for (const char* name : {"skygraph-empty.glb", "skygraph-empty.gltf"}) {
        const fs::path file = fs::temp_directory_path() / name;
        std::ofstream(file, std::ios::binary | std::ios::trunc);
        gltf_test::expectRefusedAt(file, "", "is empty (0 bytes)");
    }
}

// A buffer uri naming a directory is reported as one, not as a file that was not found.
TEST(Gltf, ABufferUriNamingADirectorySaysSo) {
    const fs::path dir = fs::temp_directory_path() / ("skygraph-buffer-uri-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "data.bin");
    const fs::path file = writeTriangle("buffer-uri", 3, false);
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const size_t uri = text.find("data:application");
    text.replace(uri, text.find('"', uri) - uri, "data.bin");
    std::ofstream(dir / "model.gltf") << text;
    Diagnostics d;
    EXPECT_FALSE(loadGltf(dir / "model.gltf", {}, d));
    EXPECT_NE(messages(d).find("data.bin' is a directory"), std::string::npos) << messages(d);
    EXPECT_EQ(messages(d).find("File not found"), std::string::npos) << messages(d);
    fs::remove_all(dir);
}

// tinygltf looks for every uri inside the glTF's folder, an absolute path too, and said "File
// not found" for /dev/zero, which exists: the uri is refused for what it is, at its JSON path.
TEST(Gltf, AnAbsoluteBufferUriIsRefusedAsAbsolute) {
    for (const std::string uri : {"/dev/zero", "/etc/passwd", "%2Fetc%2Fpasswd", "file:///etc/passwd"}) {
        SCOPED_TRACE(uri);
        const fs::path file = writeTriangle("absolute-buffer-uri", 3, false);
        std::ifstream in(file);
        std::string text((std::istreambuf_iterator<char>(in)), {});
        const size_t at = text.find("data:application");
        text.replace(at, text.find('"', at) - at, uri);
        std::ofstream(file, std::ios::trunc) << text;
        const std::string what = uri.starts_with("file:") ? "a file: URI" : "an absolute path";
        gltf_test::expectRefusedAt(file, "buffers[0].uri",
                                   "'" + uri + "' is " + what + "; a glTF uri names a file relative to the glTF "
                                   "file's folder, and absolute paths are refused");
        Diagnostics d;
        EXPECT_FALSE(loadGltf(file, {}, d));
        EXPECT_EQ(messages(d).find("File not found"), std::string::npos) << messages(d);
    }
}

TEST(Gltf, ARepeatedKeyIsRefused) {
    const fs::path file = writeTriangle("repeated-key", 3, false);
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    text.replace(text.find(R"("nodes": [{"mesh": 0}])"), 22, R"("nodes": [{"mesh": 0, "mesh": 0}])");
    std::ofstream(file, std::ios::trunc) << text;
    gltf_test::expectRefusedAt(file, "nodes[0].mesh", "duplicate key 'mesh'; JSON keeps only the last one");
}

TEST(Gltf, ANodeWithTwoParentsIsRefused) {
    // glTF's nodes form disjoint trees: drawing node 0 once per parent would double per level.
    gltf_test::expectRefusedAt(withNodes("two-parents", R"([{"mesh": 0}, {"children": [0]}, {"children": [0]}])", "[1, 2]"),
                               "nodes[2].children[0]", "node 0 is reached twice");
    gltf_test::expectRefusedAt(withNodes("root-twice", R"([{"mesh": 0}])", "[0, 0]"), "scenes[0].nodes[1]",
                               "node 0 is reached twice");
}

TEST(Gltf, AnAccessorCountPastAnyBufferIsRefusedWithoutOverflow) {
    const fs::path file = writeTriangle("huge-count", 3, false);
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const std::string count = R"("count": 3)";
    text.replace(text.find(count), count.size(), R"("count": 4611686018427387907)");
    std::ofstream(file, std::ios::trunc) << text;
    gltf_test::expectRefusedAt(file, "accessors[0] (POSITION of meshes[0].primitives[0])",
                               "4611686018427387907 elements are more than");
}

// 2^64 - 36: added to the 36 bytes three float3 elements need, the end wrapped to 0 and passed
// the check, and the elements were read from far outside the buffer.
TEST(Gltf, AnAccessorByteOffsetPastItsBufferViewIsRefusedWithoutOverflow) {
    const fs::path file = writeTriangle("huge-byte-offset", 3, false);
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const std::string view = R"("accessors": [{"bufferView": 0)";
    text.replace(text.find(view), view.size(), view + R"(, "byteOffset": 18446744073709551580)");
    std::ofstream(file, std::ios::trunc) << text;
    gltf_test::expectRefusedAt(file, "accessors[0] (POSITION of meshes[0].primitives[0])",
                               "byteOffset 18446744073709551580 lies outside its buffer view of 36 bytes");
}

TEST(Gltf, AnImageUriThatIsNotARegularFileIsNeverRead) {
    // A FIFO would block a read forever, and a directory's size is no count of bytes. Images
    // no material samples are not needed: the file loads without them (a sampled one that
    // cannot be read is refused, as any unreadable image is).
    const fs::path dir = fs::temp_directory_path() / ("skygraph-image-uris-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    ASSERT_EQ(::mkfifo((dir / "fifo.png").c_str(), 0600), 0);
    fs::create_directories(dir / "folder.png");
    for (const std::string uri : {"fifo.png", "folder.png", "."}) {
        const fs::path file = writeTriangle("image-uri", 3, false);
        std::ifstream in(file);
        std::string text((std::istreambuf_iterator<char>(in)), {});
        text.insert(text.rfind('}'), R"(, "images": [{"uri": ")" + uri + R"("}])");
        const fs::path moved = dir / "model.gltf";
        std::ofstream(moved, std::ios::trunc) << text;
        Diagnostics d;
        EXPECT_TRUE(loadGltf(moved, {}, d)) << uri << ": " << messages(d);
    }
    fs::remove_all(dir);
}

/// Whether `text` holds a control character other than the line ends that separate messages.
bool holdsControlCharacter(const std::string& text) {
    return std::any_of(text.begin(), text.end(), [](char c) {
        return c != '\n' && (static_cast<unsigned char>(c) < 0x20 || c == 0x7f);
    });
}

/// BoxTextured copied into a fresh folder `folder` of the temporary folder as `file`, every name
/// it has (scene, nodes, mesh, material, texture, image, buffer) holding control characters,
/// and its image read from a file whose name holds one too, `uri` when given (one that does
/// not exist makes the file fail); the copy.
fs::path boxWithControlCharacterNames(const std::string& folder, const std::string& file, std::string uri = "") {
    const fs::path dir = fs::temp_directory_path() / (folder + "-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path box = kModels / "BoxTextured-glTF";
    fs::copy_file(box / "BoxTextured0.bin", dir / "BoxTextured0.bin");
    fs::copy_file(box / "CesiumLogoFlat.png", dir / "logo\a.png");
    std::ifstream in(box / "BoxTextured.gltf");
    nlohmann::json gltf = nlohmann::json::parse(in);
    gltf["scenes"][0]["name"] = "scene\n";
    gltf["nodes"][0]["name"] = "root\a";
    gltf["nodes"][1]["name"] = "\x1b[31mred";
    gltf["meshes"][0]["name"] = "mesh\r\n";
    gltf["materials"][0]["name"] = "material\t\x7f";
    gltf["textures"][0]["name"] = "texture\b";
    gltf["images"][0]["name"] = "image\x01";
    gltf["images"][0]["uri"] = uri.empty() ? "logo\a.png" : uri;
    gltf["buffers"][0]["name"] = "buffer\f";
    const fs::path copy = dir / file;
    std::ofstream(copy) << gltf.dump(2);  // JSON writes each as \u0007 and so on
    return copy;
}

// Names in a glTF file are free text (glTF 2.0 does not restrict them), and skygraph never
// looks a model's part up by one: a file whose names hold control characters is valid and
// loads. What it keeps are JSON paths, and every message that names something of the file, or
// the file itself, shows control characters escaped as JSON writes them.
TEST(Gltf, NamesWithControlCharactersLoadAndMessagesShowThemEscaped) {
    Diagnostics d;
    const auto mesh = loadGltf(boxWithControlCharacterNames("skygraph-gltf-names", "box.gltf"), {}, d);
    ASSERT_TRUE(mesh) << messages(d);
    ASSERT_EQ(mesh->primitives.size(), 1u);
    EXPECT_EQ(mesh->primitives[0].name, "meshes[0].primitives[0]");
    ASSERT_EQ(mesh->images.size(), 1u);
    EXPECT_EQ(mesh->images[0].name, "images[0]");

    const fs::path broken = boxWithControlCharacterNames("skygraph-gltf-names-broken", "box\a\n.gltf", "gone\a.png");
    Diagnostics e;
    EXPECT_FALSE(loadGltf(broken, {}, e));
    ASSERT_FALSE(e.empty());
    EXPECT_EQ(e.items()[0].file, broken.string()) << "the diagnostic keeps the path as it is";
    for (const Diagnostic& x : e.items()) {
        const std::string line = x.format();
        EXPECT_FALSE(holdsControlCharacter(line) || line.find('\n') != std::string::npos) << line;
        EXPECT_EQ(line.rfind(broken.parent_path().string() + "/box\\u0007\\u000a.gltf: ", 0), 0u) << line;
    }
    EXPECT_NE(messages(e).find("gone\\u0007.png"), std::string::npos) << messages(e);
    fs::remove_all(broken.parent_path());
    fs::remove_all(mesh->file.parent_path());
}

/// assimp-testmodels' Cameras.gltf (a square and two cameras) as text, its buffer copied into
/// `dir`, which it creates: a test edits the text and writes it there.
std::string camerasGltfBesideItsBuffer(const fs::path& dir) {
    fs::create_directories(dir);
    const fs::path source = kModels / "cameras";
    fs::copy_file(source / "simpleSquare.bin", dir / "simpleSquare.bin", fs::copy_options::overwrite_existing);
    std::ifstream in(source / "Cameras.gltf");
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// glTF requires an accessor's components aligned to their size in its buffer view and buffer;
// read as it is, a misaligned one drew garbage (the model vanished) without a word.
TEST(Gltf, AMisalignedAccessorIsRefused) {
    const fs::path dir = fs::temp_directory_path() / ("skygraph-gltf-misaligned-" + std::to_string(getpid()));
    std::string text = camerasGltfBesideItsBuffer(dir);
    const std::string indices = "\"byteOffset\" : 0,\n      \"componentType\" : 5123,\n      \"count\" : 6,";
    ASSERT_NE(text.find(indices), std::string::npos);
    // Five 2-byte indices from byte 1 fit the view's 12 bytes, one byte off their alignment.
    text.replace(text.find(indices), indices.size(),
                 "\"byteOffset\" : 1,\n      \"componentType\" : 5123,\n      \"count\" : 5,");
    std::ofstream(dir / "Cameras.gltf") << text;
    Diagnostics d;
    EXPECT_FALSE(loadGltf(dir / "Cameras.gltf", {}, d));
    EXPECT_NE(messages(d).find("accessors[0] (indices of meshes[0].primitives[0]): byteOffset 1 (1 into its buffer) is "
                               "not a multiple of its components' 2 bytes, as glTF requires"),
              std::string::npos)
        << messages(d);
    fs::remove_all(dir);
}

// A camera's projection lies in the object its `type` names. Without it, or without a number
// glTF requires there, tinygltf's own words ("Orthographic camera description not found.")
// named neither the camera nor where in the file it is.
TEST(Gltf, ACameraWithoutItsProjectionIsNamedAtItsPath) {
    const fs::path dir = fs::temp_directory_path() / ("skygraph-gltf-camera-projection-" + std::to_string(getpid()));
    const std::string text = camerasGltfBesideItsBuffer(dir);
    const std::string perspective = R"("perspective": {
        "aspectRatio": 1.0,
        "yfov": 0.7,)";
    const std::string orthographic = R"("orthographic": {
        "xmag": 1.0,)";
    const struct {
        std::string from, to, path, message;
    } cases[]{
        {orthographic, R"("extras": {)", "cameras[1].orthographic",
         R"(missing; a camera of type "orthographic" describes its projection there)"},
        {perspective, R"("extras": {)", "cameras[0].perspective",
         R"(missing; a camera of type "perspective" describes its projection there)"},
        {orthographic, R"("orthographic": {)", "cameras[1].orthographic.xmag", "missing; glTF requires it here"},
        {perspective, R"("perspective": { "aspectRatio": 1.0,)", "cameras[0].perspective.yfov",
         "missing; glTF requires it here"},
        {R"("type": "perspective",)", "", "cameras[0].type", "missing; glTF requires it here"},
    };
    const fs::path file = dir / "Cameras.gltf";
    for (const auto& c : cases) {
        SCOPED_TRACE(c.path);
        ASSERT_NE(text.find(c.from), std::string::npos) << c.from;
        std::string edited = text;
        edited.replace(edited.find(c.from), c.from.size(), c.to);
        std::ofstream(file, std::ios::trunc) << edited;
        Diagnostics d;
        EXPECT_FALSE(loadGltf(file, {}, d));
        ASSERT_FALSE(d.empty());
        EXPECT_NE(d.items()[0].format().find(file.string() + ": " + c.path + ": " + c.message), std::string::npos)
            << messages(d);
    }
    fs::remove_all(dir);
}

TEST(Gltf, NotAGltfFile) {
    Diagnostics d;
    EXPECT_FALSE(loadGltf(fs::path(SKYGRAPH_SOURCE_DIR) / "scenes/default.json", {}, d));
    EXPECT_NE(messages(d).find("neither a .gltf nor a .glb"), std::string::npos);
    Diagnostics e;
    EXPECT_FALSE(loadGltf("/nonexistent/model.glb", {}, e));
    EXPECT_NE(messages(e).find("does not exist"), std::string::npos);
}

// ---- textures, texture coordinates and tangents ----

/// The width and height in a PNG file's IHDR chunk, read without stb.
// ---- through scene files ----

Scene parse(const std::string& text) { return parseScene(text, "test.json", fs::path("/")); }

TEST(GltfScene, AModelAndItsCamera) {
    const Scene s = parse(R"({"camera": "gltf", "objects": [{"type": "gltf",
        "file": ")" + (kModels / "2CylinderEngine-glTF-Binary/2CylinderEngine.glb").string() + R"("}]})");
    ASSERT_EQ(s.objects.size(), 1u);
    const auto& model = std::get<GltfModel>(s.objects[0].shape);
    ASSERT_TRUE(model.mesh && model.mesh->camera);
    const MeshCamera& c = *model.mesh->camera;
    EXPECT_EQ(s.camera.position, c.position);
    EXPECT_NEAR(s.camera.fovYDeg, c.fovYDeg, 1e-12);
    // The yaw and pitch the loader derived give the file's view direction back.
    const Vec3 forward = cameraForward(s.camera);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(forward[size_t(i)], c.forward[size_t(i)], 1e-9);
}

TEST(GltfScene, AGltfCameraNeedsAModelWithOne) {
    try {
        (void)parse(R"({"camera": "gltf", "objects": [{"type": "gltf",
            "file": ")" + (kModels / "BoxTextured-glTF/BoxTextured.gltf").string() + R"("}]})");
        FAIL() << "no camera in the box";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("camera: is \"gltf\", but no glTF object"), std::string::npos) << e.what();
    }
}

// A glTF camera's values become the scene's camera, which the GPU reads as 32-bit floats: a
// near plane or a position a float does not hold is refused as camera.near and
// camera.position are (before, the frame showed only the sky and the command succeeded).
TEST(GltfScene, AGltfCameraPastAFloatsRangeIsRefused) {
    const fs::path dir = fs::temp_directory_path() / ("skygraph-gltf-camera-range-" + std::to_string(getpid()));
    const std::string text = camerasGltfBesideItsBuffer(dir);
    const auto refusal = [&](const std::string& from, const std::string& to, const std::string& before = "") {
        std::string edited = text;
        const size_t at = edited.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) edited.replace(at, from.size(), to);
        std::ofstream(dir / "Cameras.gltf") << edited;
        try {
            (void)parse(R"({"camera": "gltf", "objects": [)" + before + R"({"type": "gltf", "file": ")" +
                        (dir / "Cameras.gltf").string() + R"("}]})");
        } catch (const SceneError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(refusal("\"znear\": 0.01", "\"znear\": 1e-300")
                  .find("test.json: camera: objects[0]'s glTF camera has the position [0.5, 0.5, 3] and near plane "
                        "1e-300: each must be 0 or of a magnitude a 32-bit float holds (1.2e-38 to 3.4e38), as the "
                        "scene's camera's"),
              std::string::npos);
    EXPECT_NE(refusal("\"translation\" : [ 0.5, 0.5, 3.0 ]", "\"translation\" : [ 0.5, 1e300, 3.0 ]")
                  .find("position [0.5, 1e+300, 3] and near plane 0.01"),
              std::string::npos);
    EXPECT_EQ(refusal("\"znear\": 0.01", "\"znear\": 0.02"), "accepted");
    EXPECT_NE(refusal("\"znear\": 0.01", "\"znear\": 1e-9")
                  .find("test.json: camera: objects[0]'s glTF camera's znear must be at least 1e-6"),
              std::string::npos);
    const std::string yfov = "\"yfov\": 0.7";
    // A view narrower than the scene's camera may have: its projection leaves a float's range
    // (1e-37 degrees drew only the sky, and the command succeeded).
    EXPECT_NE(refusal(yfov, "\"yfov\": 1e-300").find("test.json: camera: objects[0]'s glTF camera's yfov is 5.72957795e-299 "
                                                      "degrees, narrower than the 0.001 degrees"),
              std::string::npos);
    EXPECT_EQ(refusal(yfov, "\"yfov\": 1.75e-5"), "accepted");  // 0.0010027 degrees
    // A coordinate that the node transforms leave below a float's smallest normal is 0.
    EXPECT_EQ(refusal("\"translation\" : [ 0.5, 0.5, 3.0 ]", "\"translation\" : [ 0.5, 1e-40, 3.0 ]"), "accepted");
    // Behind an object that did not load, the camera's object would be misnumbered: that
    // object's error is the scene's.
    const std::string behind = refusal("\"znear\": 0.01", "\"znear\": 1e-300", R"({"type": "cube"}, )");
    EXPECT_NE(behind.find("objects[0].type"), std::string::npos) << behind;
    EXPECT_EQ(behind.find("glTF camera"), std::string::npos) << behind;
    fs::remove_all(dir);
}

// glTF uris are RFC 3986 references: a '+' in one is a '+'. tinygltf decodes them as HTML
// forms do, '+' as a space, and looked for "simple Square.bin".
TEST(GltfScene, APlusInABufferUriIsAPlus) {
    const fs::path dir = fs::temp_directory_path() / ("skygraph-gltf-plus-" + std::to_string(getpid()));
    std::string text = camerasGltfBesideItsBuffer(dir);
    const std::string uri = "\"uri\" : \"simpleSquare.bin\"";
    ASSERT_NE(text.find(uri), std::string::npos);
    const auto load = [&](const std::string& referenced) {
        std::string edited = text;
        edited.replace(edited.find(uri), uri.size(), "\"uri\" : \"" + referenced + "\"");
        std::ofstream(dir / "Cameras.gltf") << edited;
        try {
            (void)parse(R"({"camera": "gltf", "objects": [{"type": "gltf", "file": ")" +
                                      (dir / "Cameras.gltf").string() + R"("}]})");
            return std::string("loaded");
        } catch (const SceneError& e) {
            return std::string(e.what());
        }
    };
    fs::rename(dir / "simpleSquare.bin", dir / "simple+Square.bin");
    EXPECT_EQ(load("simple+Square.bin"), "loaded");
    EXPECT_EQ(load("simple%2BSquare.bin"), "loaded");
    fs::rename(dir / "simple+Square.bin", dir / "simple Square.bin");
    EXPECT_EQ(load("simple%20Square.bin"), "loaded");
    EXPECT_NE(load("simple+Square.bin"), "loaded") << "a '+' is not a space";
    fs::remove_all(dir);
}

TEST(GltfScene, TheSceneNamesItsObjectAndTheFileItsProblem) {
    const std::string bad = (kModels / "IndexOutOfRange/IndexOutOfRange.gltf").string();
    try {
        (void)parse(R"({"objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1},
                                    {"type": "gltf", "file": ")" + bad + R"(", "transform": {"scale": 2}}]})");
        FAIL() << "a bad glTF file must fail the scene";
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("test.json: objects[1].file: '" + bad + "' cannot be drawn"), std::string::npos) << what;
        EXPECT_NE(what.find(bad + ": accessors[0] (indices of meshes[0].primitives[0])"), std::string::npos) << what;
    }
}

// A scene's glTF file named with control characters, with a problem: each diagnostic, the
// scene's and the file's, is one line with them escaped.
TEST(GltfScene, AGltfFileNamedWithControlCharactersIsShownEscaped) {
    const fs::path broken = boxWithControlCharacterNames("skygraph-gltf-scene-names", "box\a\x1b.gltf", "gone\n.png");
    try {
        (void)parse(R"({"objects": [{"type": "gltf", "file": )" + nlohmann::json(broken.string()).dump() + "}]}");
        FAIL() << "the image is missing";
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_FALSE(holdsControlCharacter(what)) << what;
        size_t lines = 0;
        for (const char c : what) lines += c == '\n';
        EXPECT_EQ(lines, e.diagnostics().size()) << what;
        const std::string shown = broken.parent_path().string() + "/box\\u0007\\u001b.gltf";
        EXPECT_NE(what.find("test.json: objects[0].file: '" + shown + "' cannot be drawn"), std::string::npos) << what;
        EXPECT_NE(what.find("\n" + shown + ": "), std::string::npos) << what;
        EXPECT_NE(what.find("gone\\u000a.png"), std::string::npos) << what;
    }
    fs::remove_all(broken.parent_path());
}

TEST(GltfScene, TransformAndKeysAreChecked) {
    const std::string box = (kModels / "BoxTextured-glTF/BoxTextured.gltf").string();
    try {
        (void)parse(R"({"objects": [{"type": "gltf", "file": ")" + box +
                    R"(", "material": {}, "transform": {"scale": [1, 0, 1], "spin": 1}}]})");
        FAIL();
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("objects[0].material: unknown key"), std::string::npos) << what;
        EXPECT_NE(what.find("objects[0].transform.spin: unknown key"), std::string::npos) << what;
        EXPECT_NE(what.find("objects[0].transform.scale[1]: must be > 0"), std::string::npos) << what;
    }
}

}  // namespace
}  // namespace skygraph
