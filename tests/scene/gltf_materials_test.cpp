// glTF materials through loadGltf(): decoded textures, their samplers and settings, texture
// coordinates and tangents, on Debian's assimp-testmodels and on small files written here.
#include "gltf_test_util.hpp"

#include <skygraph/scene.hpp>
#include <skygraph/triangle_mesh.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

namespace skygraph {
namespace {

namespace fs = std::filesystem;
using gltf_test::kModels;
using gltf_test::messages;

std::pair<uint32_t, uint32_t> pngSize(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    unsigned char header[24] = {};
    in.read(reinterpret_cast<char*>(header), sizeof header);
    const auto bigEndian = [&](size_t at) {
        return uint32_t(header[at]) << 24 | uint32_t(header[at + 1]) << 16 | uint32_t(header[at + 2]) << 8 |
               header[at + 3];
    };
    return {bigEndian(16), bigEndian(20)};
}

double length3(const float* v) { return std::hypot(v[0], v[1], v[2]); }
double dot3(const float* a, const float* b) { return double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2]; }

/// What every loaded vertex must have: a unit tangent orthogonal to its normal, w = +1 or -1.
void expectTangentFrames(const TriangleMesh& mesh) {
    for (const MeshVertex& v : mesh.vertices) {
        EXPECT_NEAR(length3(v.tangent), 1.0, 1e-4);
        EXPECT_LT(std::abs(dot3(v.tangent, v.normal)), 1e-3);
        EXPECT_EQ(std::abs(v.tangent[3]), 1.0f);
    }
}

TEST(GltfTextures, TheBoxSamplesItsLogo) {
    Diagnostics d;
    const auto box = loadGltf(kModels / "BoxTextured-glTF/BoxTextured.gltf", {}, d);
    ASSERT_TRUE(box) << messages(d);
    ASSERT_EQ(box->images.size(), 1u);
    const MeshImage& logo = box->images[0];
    const auto [width, height] = pngSize(kModels / "BoxTextured-glTF/CesiumLogoFlat.png");  // 211 x 211
    EXPECT_EQ(logo.width, width);
    EXPECT_EQ(logo.height, height);
    EXPECT_EQ(logo.rgba.size(), size_t(width) * height * 4);
    EXPECT_EQ(logo.name, "images[0]");
    const MeshMaterial& m = box->primitives.at(0).material;
    EXPECT_EQ(m.baseColorTexture.image, 0);
    EXPECT_EQ(m.baseColorTexture.wrapS, MeshWrap::MirroredRepeat);  // the file's sampler: 33648
    EXPECT_EQ(m.baseColorTexture.wrapT, MeshWrap::ClampToEdge);     // and 33071
    for (const MeshTexture* t :
         {&m.metallicRoughnessTexture, &m.normalTexture, &m.occlusionTexture, &m.emissiveTexture})
        EXPECT_FALSE(t->present());
    // The file's TEXCOORD_0 spans its accessor's min and max, [0, 6] x [0, 1]: the logo repeats,
    // mirrored, six times along U.
    float low[2] = {1e9f, 1e9f}, high[2] = {-1e9f, -1e9f};
    for (const MeshVertex& v : box->vertices)
        for (int c = 0; c < 2; ++c) {
            low[c] = std::min(low[c], v.uv[c]);
            high[c] = std::max(high[c], v.uv[c]);
        }
    EXPECT_EQ(low[0], 0.0f);
    EXPECT_EQ(low[1], 0.0f);
    EXPECT_EQ(high[0], 6.0f);
    EXPECT_EQ(high[1], 1.0f);
    expectTangentFrames(*box);
}

TEST(GltfTextures, OnlyWhatDrawnMaterialsSampleIsDecoded) {
    Diagnostics d;
    const auto test = loadGltf(kModels / "ClearCoat-glTF/ClearCoatTest.gltf", {}, d);
    ASSERT_TRUE(test) << messages(d);
    // images[0] (PartialCoating.png) is sampled only through KHR_materials_clearcoat, which
    // skygraph ignores; images[4] is a JPEG.
    std::vector<std::string> names;
    for (const MeshImage& image : test->images) names.push_back(image.name);
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"images[1]", "images[2]", "images[3]", "images[4]", "images[5]"}));
    size_t normalMapped = 0, blended = 0;
    for (const MeshPrimitive& p : test->primitives) {
        if (p.material.normalTexture.present()) {
            ++normalMapped;
            const MeshImage& normals = test->images.at(size_t(p.material.normalTexture.image));
            EXPECT_TRUE(normals.name == "images[3]" || normals.name == "images[4]") << normals.name;
            EXPECT_EQ(normals.width, normals.name == "images[3]" ? 512u : 1024u);
            EXPECT_EQ(p.material.normalScale, 1.0);
        }
        if (p.material.alphaMode == MeshAlphaMode::Blend) {
            ++blended;
            EXPECT_EQ(test->images.at(size_t(p.material.baseColorTexture.image)).name, "images[1]");
        }
    }
    EXPECT_EQ(normalMapped, 6u);  // materials 9, 10 and 14 to 17
    EXPECT_EQ(blended, 1u);
    expectTangentFrames(*test);
}

std::string base64(const std::string& bytes) {
    static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const size_t n = std::min<size_t>(3, bytes.size() - i);
        uint32_t group = 0;
        for (size_t k = 0; k < 3; ++k) group = group << 8 | (k < n ? uint8_t(bytes[i + k]) : 0u);
        for (size_t k = 0; k < 4; ++k) out += k <= n ? digits[(group >> (18 - 6 * k)) & 63] : '=';
    }
    return out;
}

/// A unit quad in the XY plane facing +Z, corners (0,0) (1,0) (1,1) (0,1), as a .gltf with its
/// buffer embedded: POSITION, NORMAL, and TEXCOORD_0 and TANGENT where given.
struct Quad {
    std::vector<float> uvs;       ///< 2 a corner, or none
    std::vector<float> tangents;  ///< 4 a corner, or none
    std::string material;         ///< materials[0], which the quad then uses
    std::string more;             ///< further top-level members: textures, images, samplers
    std::string node = R"({"mesh": 0})";
    std::vector<uint16_t> uvShorts;  ///< TEXCOORD_0 as normalized UNSIGNED_SHORT instead
    std::vector<uint8_t> uvBytes;    ///< or UNSIGNED_BYTE
};

/// A 1x1 RGBA PNG, in base64; as a Quad's `more` members; and a texture of it.
const std::string kPixelPng =
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg==";
const std::string kPixelImage = R"("images": [{"uri": "data:image/png;base64,)" + kPixelPng + R"("}])";
const std::string kPixelTexture = R"("textures": [{"source": 0}], )" + kPixelImage;
const std::vector<float> kUpright{0, 1, 1, 1, 1, 0, 0, 0};  ///< the image upright on the quad: v = 0 at the top

fs::path writeQuad(const std::string& name, const Quad& q, const fs::path& dir = fs::temp_directory_path()) {
    std::string bytes, views, accessors, attributes;
    int count = 0;
    const auto add = [&](const char* attribute, const auto& values, int componentType, const char* type) {
        if (values.empty()) return;
        const size_t length = values.size() * sizeof(values[0]);
        const std::string index = std::to_string(count++), separator = index == "0" ? "" : ", ";
        views += separator + R"({"buffer": 0, "byteOffset": )" + std::to_string(bytes.size()) + R"(, "byteLength": )" +
                 std::to_string(length) + "}";
        const std::string normalized = componentType == 5126 ? "" : R"(, "normalized": true)";
        accessors += separator + R"({"bufferView": )" + index + R"(, "componentType": )" +
                     std::to_string(componentType) + normalized + R"(, "count": 4, "type": ")" + type + "\"}";
        attributes += separator + "\"" + attribute + "\": " + index;
        bytes.append(reinterpret_cast<const char*>(values.data()), length);
    };
    add("POSITION", std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, 5126, "VEC3");
    add("NORMAL", std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, 5126, "VEC3");
    add("TEXCOORD_0", q.uvs, 5126, "VEC2");
    add("TEXCOORD_0", q.uvShorts, 5123, "VEC2");
    add("TEXCOORD_0", q.uvBytes, 5121, "VEC2");
    add("TANGENT", q.tangents, 5126, "VEC4");
    const std::string indices = std::to_string(count);
    const std::vector<uint32_t> corners{0, 1, 2, 0, 2, 3};
    views += R"(, {"buffer": 0, "byteOffset": )" + std::to_string(bytes.size()) + R"(, "byteLength": 24})";
    accessors += R"(, {"bufferView": )" + indices + R"(, "componentType": 5125, "count": 6, "type": "SCALAR"})";
    bytes.append(reinterpret_cast<const char*>(corners.data()), 24);
    const std::string material = q.material.empty() ? "" : R"(, "material": 0)";
    const std::string materials = q.material.empty() ? "" : R"(, "materials": [)" + q.material + "]";
    const fs::path file = dir / ("skygraph-" + name + ".gltf");
    std::ofstream(file) << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [)"
                        << q.node << R"(], "meshes": [{"primitives": [{"attributes": {)" << attributes
                        << R"(}, "indices": )" << indices << material << "}]}]" << materials
                        << (q.more.empty() ? "" : ", " + q.more) << R"(, "accessors": [)" << accessors
                        << R"(], "bufferViews": [)" << views << R"(], "buffers": [{"byteLength": )" << bytes.size()
                        << R"(, "uri": "data:application/octet-stream;base64,)" << base64(bytes) << R"("}]})";
    return file;
}

TEST(GltfTextures, MaterialsKeepTheirTexturesAndSettings) {
    Quad q{kUpright, {}, R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
        "metallicRoughnessTexture": {"index": 0}}, "normalTexture": {"index": 0, "scale": 0.5},
        "occlusionTexture": {"index": 0, "strength": 0.25}, "emissiveTexture": {"index": 0},
        "alphaMode": "MASK", "alphaCutoff": 0.125, "doubleSided": true})"};
    q.more = R"("samplers": [{"wrapS": 33071, "wrapT": 33648}], "textures": [{"source": 0, "sampler": 0}], )" +
             kPixelImage;
    Diagnostics d;
    const auto quad = loadGltf(writeQuad("material", q), {}, d);
    ASSERT_TRUE(quad) << messages(d);
    ASSERT_EQ(quad->images.size(), 1u) << "one image, however many textures sample it";
    const MeshMaterial& m = quad->primitives.at(0).material;
    for (const MeshTexture* t : {&m.baseColorTexture, &m.metallicRoughnessTexture, &m.normalTexture,
                                 &m.occlusionTexture, &m.emissiveTexture}) {
        EXPECT_EQ(t->image, 0);
        EXPECT_EQ(t->wrapS, MeshWrap::ClampToEdge);
        EXPECT_EQ(t->wrapT, MeshWrap::MirroredRepeat);
    }
    EXPECT_EQ(m.normalScale, 0.5);
    EXPECT_EQ(m.occlusionStrength, 0.25);
    EXPECT_EQ(m.alphaMode, MeshAlphaMode::Mask);
    EXPECT_EQ(m.alphaCutoff, 0.125);
    EXPECT_TRUE(m.doubleSided);
}

TEST(GltfTextures, SixteenBitImagesAreDecodedToEightBits) {
    // A 2x1 RGBA PNG of 16-bit channels: (FFFF 8080 0000 FFFF) (0101 0000 FEFF 7FFF).
    const std::string png = "iVBORw0KGgoAAAANSUhEUgAAAAIAAAABEAYAAACksqPJAAAAGklEQVR4nGP4/7+hgYHh/39GRgaGf//r/"
                            "wMASGAIejrLmDIAAAAASUVORK5CYII=";
    const Quad q{kUpright, {}, R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}})",
                 R"("textures": [{"source": 0}], "images": [{"uri": "data:image/png;base64,)" + png + R"("}])"};
    Diagnostics d;
    const auto quad = loadGltf(writeQuad("sixteen-bit", q), {}, d);
    ASSERT_TRUE(quad) << messages(d);
    ASSERT_EQ(quad->images.size(), 1u);
    EXPECT_EQ(quad->images[0].width, 2u);
    EXPECT_EQ(quad->images[0].rgba, (std::vector<uint8_t>{255, 128, 0, 255, 1, 0, 254, 127})) << "the high bytes";
    const MeshTexture& t = quad->primitives.at(0).material.baseColorTexture;
    EXPECT_EQ(t.wrapS, MeshWrap::Repeat) << "no sampler: glTF's default";
    EXPECT_EQ(t.wrapT, MeshWrap::Repeat);
}

TEST(GltfTextures, NormalizedIntegerTexCoordsSpanZeroToOne) {
    Quad shorts, bytes;
    shorts.uvShorts = {0, 65535, 65535, 65535, 65535, 0, 13107, 0};
    bytes.uvBytes = {0, 255, 255, 255, 255, 0, 51, 0};
    Diagnostics d;
    for (const auto& [name, quad] : {std::pair{"uv-shorts", shorts}, std::pair{"uv-bytes", bytes}}) {
        const auto mesh = loadGltf(writeQuad(name, quad), {}, d);
        ASSERT_TRUE(mesh) << messages(d);
        const std::vector<float> expected{0, 1, 1, 1, 1, 0, 0.2f, 0};
        for (size_t i = 0; i < 8; ++i)
            EXPECT_FLOAT_EQ(mesh->vertices.at(i / 2).uv[i % 2], expected[i]) << name << " " << i;
    }
}

/// Writes, in a folder of its own, a quad textured with `file`, holding `bytes` where given.
fs::path writeTexturedQuad(const std::string& name, const std::string& file, const std::string* bytes, bool sampled) {
    const fs::path dir = fs::temp_directory_path() / ("skygraph-" + name);
    fs::create_directories(dir);
    fs::remove(dir / file);
    if (bytes) std::ofstream(dir / file, std::ios::binary) << *bytes;
    const std::string material = sampled ? R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}})" : "{}";
    const std::string image = R"("textures": [{"source": 0}], "images": [{"uri": ")" + file + "\"}]";
    return writeQuad(name, {kUpright, {}, material, image}, dir);
}

std::string fileBytes(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

// An image file that cannot be used is named as the loader looked for it, its uri resolved
// against the glTF file's folder, at its uri's JSON path in the glTF file.
TEST(GltfTextures, AnImageThatCannotBeDecodedIsRefusedNamingItsFile) {
    // The logo cut short: its header reads, its pixels do not.
    const std::string truncated = fileBytes(kModels / "BoxTextured-glTF/CesiumLogoFlat.png").substr(0, 600);
    const std::string garbage(300, 'x');
    const std::string empty;
    // Formats stb reads and glTF does not have, whose Debian stb readers misbehave: a 16-bit
    // PGM (read past its pixels), a Radiance file with a zero run length (a loop that never
    // ends), a GIF cut short (filled in silently).
    const std::string pgm16 = "P5 16 16 65535\n" + std::string(512, '\x7f');
    const std::string zeroRun = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n" + std::string("\x02\x02\x00\x08", 4) +
                                std::string(4, '\0');
    const std::string gif = std::string("GIF89a\x10\x00\x10\x00\x00\x00\x00", 13) + std::string("\x2c", 1) +
                            std::string(9, '\0') + std::string("\x02", 1);
    // A JPEG header claiming 4096x4096 and no coded data: stb would fill 64 MiB of zeros.
    const std::string hollowJpeg = std::string("\xff\xd8\xff\xc0\x00\x0b\x08\x10\x00\x10\x00\x01\x01\x11\x00"
                                               "\xff\xd9", 17);
    struct Case {
        std::string name, uri;
        const std::string* bytes;
        std::string image;  ///< the file named, relative to the glTF file's folder
        std::string message;
    };
    for (const Case& c : {Case{"truncated", "logo.png", &truncated, "logo.png", "cannot be decoded"},
                          Case{"garbage", "logo.png", &garbage, "logo.png", "is neither a PNG nor a JPEG file"},
                          Case{"pgm16", "logo.pgm", &pgm16, "logo.pgm", "is neither a PNG nor a JPEG file"},
                          Case{"radiance", "sky.hdr", &zeroRun, "sky.hdr", "is neither a PNG nor a JPEG file"},
                          Case{"gif", "logo.gif", &gif, "logo.gif", "is neither a PNG nor a JPEG file"},
                          Case{"hollow-jpeg", "logo.jpg", &hollowJpeg, "logo.jpg",
                               "is a JPEG of 4096x4096, whose 262144 blocks take at least 32768 bytes, but it has 17: "
                               "it is cut short"},
                          Case{"empty", "logo.png", &empty, "logo.png", "is empty"},
                          Case{"missing", "absent.png", nullptr, "absent.png", "does not exist"},
                          // A '+' in a uri is a '+' (RFC 3986), as the loader reads the file.
                          Case{"plus", "my+logo.png", &truncated, "my+logo.png", "cannot be decoded"},
                          Case{"missing-plus", "absent+logo.png", nullptr, "absent+logo.png", "does not exist"},
                          Case{"missing-in-folder", "textures/absent%20logo.png", nullptr, "textures/absent logo.png",
                               "does not exist"}}) {
        SCOPED_TRACE(c.name);
        const fs::path file = writeTexturedQuad("image-" + c.name, c.uri, c.bytes, true);
        const std::string named = "image file '" + (file.parent_path() / c.image).string() + "': " + c.message;
        Diagnostics d;
        EXPECT_FALSE(loadGltf(file, {}, d));
        ASSERT_FALSE(d.empty());
        EXPECT_EQ(d.items()[0].file, file.string());
        EXPECT_EQ(d.items()[0].jsonPath, "images[0].uri") << messages(d);
        EXPECT_NE(d.items()[0].message.find(named), std::string::npos) << messages(d);
    }
}

// An absolute image path is never looked for (tinygltf would look inside the glTF's folder and
// only warn): the file is refused, sampled or not, saying that uris are relative to it.
TEST(GltfTextures, AnAbsoluteImageUriIsRefusedAsAbsolute) {
    const std::string sampling = R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}})";
    struct Case {
        std::string uri, material;
    };
    for (const Case& c : {Case{"/etc/passwd", sampling}, Case{"%2Fetc%2Fpasswd", sampling},
                          Case{"file:///etc/passwd", sampling}, Case{"/etc/passwd", "{}"}}) {
        SCOPED_TRACE(c.uri + " " + c.material);
        const std::string image = R"("textures": [{"source": 0}], "images": [{"uri": ")" + c.uri + "\"}]";
        const fs::path file = writeQuad("image-absolute", {kUpright, {}, c.material, image});
        Diagnostics d;
        EXPECT_FALSE(loadGltf(file, {}, d));
        ASSERT_FALSE(d.empty());
        EXPECT_EQ(d.items()[0].jsonPath, "images[0].uri") << messages(d);
        const std::string what = c.uri.starts_with("file:") ? "a file: URI" : "an absolute path";
        EXPECT_NE(d.items()[0].message.find("'" + c.uri + "' is " + what + "; a glTF uri names a file relative to the "
                                            "glTF file's folder, and absolute paths are refused"),
                  std::string::npos)
            << messages(d);
    }
}

TEST(GltfTextures, AnImageNothingSamplesIsNotDecoded) {
    const std::string truncated = fileBytes(kModels / "BoxTextured-glTF/CesiumLogoFlat.png").substr(0, 600);
    Diagnostics d;
    const auto quad = loadGltf(writeTexturedQuad("image-unsampled", "logo.png", &truncated, false), {}, d);
    ASSERT_TRUE(quad) << messages(d);
    EXPECT_TRUE(quad->images.empty());
}

// KHR_texture_basisu and EXT_texture_webp name their image inside the texture's extension and
// keep `source` for a fallback, which a loader without the extension samples (glTF 2.0,
// "Specifying Extensions"). The KTX2 or WebP image, which stb cannot read, was refused.
TEST(GltfTextures, AnImageOnlyAnIgnoredExtensionNamesIsNotRequired) {
    struct Case {
        std::string extension, file, bytes;
    };
    const std::string ktx2 = std::string("\xABKTX 20\xBB\r\n\x1A\n", 12) + std::string(68, '\0');
    const std::string webp = std::string("RIFF\x48\0\0\0WEBPVP8 ", 16) + std::string(64, '\0');
    for (const Case& c : {Case{"KHR_texture_basisu", "logo.ktx2", ktx2}, Case{"EXT_texture_webp", "logo.webp", webp}}) {
        SCOPED_TRACE(c.extension);
        const fs::path dir = fs::temp_directory_path() / ("skygraph-fallback-" + c.file);
        fs::create_directories(dir);
        std::ofstream(dir / c.file, std::ios::binary) << c.bytes;
        Quad q{kUpright, {}, R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}})"};
        q.more = R"("extensionsUsed": [")" + c.extension + R"("], "textures": [{"source": 0, "extensions": {")" +
                 c.extension + R"(": {"source": 1}}}], "images": [{"uri": "data:image/png;base64,)" + kPixelPng +
                 R"("}, {"uri": ")" + c.file + "\"}]";
        Diagnostics d;
        const auto quad = loadGltf(writeQuad("fallback-" + c.extension, q, dir), {}, d);
        ASSERT_TRUE(quad) << messages(d);
        ASSERT_EQ(quad->images.size(), 1u);
        EXPECT_EQ(quad->images[0].name, "images[0]") << "the fallback";
        EXPECT_EQ(quad->primitives.at(0).material.baseColorTexture.image, 0);

        // A file that requires the extension has no fallback to offer.
        q.more = R"("extensionsRequired": [")" + c.extension + R"("], )" + q.more;
        gltf_test::expectRefusedAt(
            writeQuad("required-" + c.extension, q, dir), "extensionsRequired",
            "the file requires extension '" + c.extension + "', which skygraph does not support");
    }
}

/// A PNG of nothing but its signature and header, claiming `width` x `height` RGBA8 texels: a
/// few bytes that would make a decoder take width * height * 4 bytes and more.
std::string forgedPngHeader(uint32_t width, uint32_t height) {
    std::string png = "\x89PNG\r\n\x1a\n";
    const auto bigEndian = [&](uint32_t v) {
        for (int shift = 24; shift >= 0; shift -= 8) png += char(v >> shift & 0xff);
    };
    bigEndian(13);
    png += "IHDR";
    bigEndian(width);
    bigEndian(height);
    png += std::string("\x08\x06\x00\x00\x00", 5);  // 8 bits, RGBA, deflate, no filter, no interlace
    bigEndian(0);                                        // stb does not check chunk CRCs
    return png;
}

TEST(GltfTextures, ForgedImageSizesAreRefusedBeforeAnyPixelIsDecoded) {
    struct Case {
        std::string name;
        uint32_t width, height;
        GltfLimits limits;
        std::string path, message;
    };
    GltfLimits fewBytes, narrow;
    fewBytes.maxImageBytes = size_t(64) << 20;
    narrow.maxTextureSide = 4096;
    for (const Case& c :
         {Case{"wide", 16385, 1, {}, "images[0].uri", "16385x1 is larger than 16384 texels a side"},
          // stb's own reading refuses this one (over 2^30 bytes) as no image at all
          Case{"past-stb", 20000, 20000, {}, "images[0].uri", "20000x20000 is larger than 16384 texels a side"},
          Case{"narrow-limit", 1, 4097, narrow, "images[0].uri", "1x4097 is larger than 4096 texels a side"},
          // the images of the file together, not this one's file, are too large
          Case{"byte-limit", 8192, 8192, fewBytes, "images[0]",
               "the file's images would take 268435456 bytes, more than 67108864"}}) {
        const std::string png = forgedPngHeader(c.width, c.height);
        SCOPED_TRACE(c.name);
        gltf_test::expectRefusedAt(writeTexturedQuad("forged-" + c.name, "forged.png", &png, true), c.path,
                                   c.message, c.limits);
    }
}

// A 2x2 PNG whose IDAT chunk declares 800 MB: stb would grow its buffer to that before reading.
TEST(GltfTextures, AForgedPngChunkLengthIsRefusedBeforeAnyPixelIsDecoded) {
    std::string png = forgedPngHeader(2, 2);
    png += std::string("\x30\x00\x00\x00", 4);  // 805,306,368 bytes, big-endian
    png += "IDAT";
    png += std::string(16, '\0');
    gltf_test::expectRefusedAt(writeTexturedQuad("forged-chunk", "forged.png", &png, true), "images[0].uri",
                               "declares 805306368 bytes, past the end of the image's");
}

struct BadQuad {
    std::string name;
    Quad quad;
    std::string path;     ///< the JSON path the first diagnostic names
    std::string message;  ///< part of its message
};

void PrintTo(const BadQuad& b, std::ostream* out) { *out << b.name; }

class BadTexturing : public ::testing::TestWithParam<BadQuad> {};

TEST_P(BadTexturing, IsRefusedNamingThePlace) {
    const BadQuad& b = GetParam();
    Diagnostics d;
    const fs::path file = writeQuad("bad-" + b.name, b.quad);
    EXPECT_FALSE(loadGltf(file, {}, d));
    ASSERT_FALSE(d.empty());
    EXPECT_EQ(d.items()[0].file, file.string());
    EXPECT_EQ(d.items()[0].jsonPath, b.path) << messages(d);
    EXPECT_NE(d.items()[0].message.find(b.message), std::string::npos) << messages(d);
}

// tinygltf quotes what it could not read: a data URI buffer one byte shorter than its
// byteLength came back with its whole base64 in the message. Each line is cut short.
TEST(GltfErrors, TinygltfsMessagesDoNotQuoteWholeDataUris) {
    const fs::path file = writeQuad("short-buffer", Quad{std::vector<float>(8 * 64, 0.5f)});
    std::ifstream in(file);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t at = text.find(R"("buffers": [{"byteLength": )");
    ASSERT_NE(at, std::string::npos);
    const size_t number = at + std::string(R"("buffers": [{"byteLength": )").size();
    const size_t end = text.find(',', number);
    text.replace(number, end - number, std::to_string(std::stoul(text.substr(number, end - number)) + 1));
    std::ofstream(file) << text;
    Diagnostics d;
    EXPECT_FALSE(loadGltf(file, {}, d));
    ASSERT_FALSE(d.empty());
    bool cut = false;
    for (const Diagnostic& x : d.items()) {
        EXPECT_LT(x.message.size(), 320u) << x.message.substr(0, 400);
        cut |= x.message.find(" more bytes)") != std::string::npos;
    }
    EXPECT_TRUE(cut) << messages(d).substr(0, 2000);
}

const std::string kBaseColorTexture = R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}})";
const float kNaN = std::numeric_limits<float>::quiet_NaN();

INSTANTIATE_TEST_SUITE_P(
    WrittenQuads, BadTexturing,
    ::testing::Values(
        BadQuad{"texcoord", {kUpright, {}, R"({"emissiveTexture": {"index": 0, "texCoord": 1}})", kPixelTexture},
                "materials[0].emissiveTexture.texCoord", "TEXCOORD_1 is not supported: skygraph reads TEXCOORD_0 only"},
        BadQuad{"no-uvs", {{}, {}, kBaseColorTexture, kPixelTexture}, "meshes[0].primitives[0]", "has no TEXCOORD_0"},
        BadQuad{"nan-uv", {{0, 1, kNaN, 1, 1, 0, 0, 0}}, "accessors[2] (TEXCOORD_0 of meshes[0].primitives[0])",
                "element 1 is not finite"},
        BadQuad{"zero-tangent", {{}, std::vector<float>(16, 0.0f)}, "accessors[2] (TANGENT of meshes[0].primitives[0])",
                "tangent 0 has length 0"},
        BadQuad{"source-missing", {kUpright, {}, kBaseColorTexture, R"("textures": [{}])"}, "textures[0].source",
                "is missing (materials[0].pbrMetallicRoughness.baseColorTexture samples the texture)"},
        BadQuad{"source-past", {kUpright, {}, kBaseColorTexture, R"("textures": [{"source": 3}])"},
                "textures[0].source", "image 3 does not exist"},
        BadQuad{"sampler-past",
                {kUpright, {}, kBaseColorTexture, R"("textures": [{"source": 0, "sampler": 2}], )" + kPixelImage},
                "textures[0].sampler", "sampler 2 does not exist"},
        BadQuad{"wrap",
                {kUpright, {}, kBaseColorTexture,
                 R"("samplers": [{"wrapT": 9729}], "textures": [{"source": 0, "sampler": 0}], )" + kPixelImage},
                "samplers[0].wrapT",
                "must be 10497 (REPEAT), 33071 (CLAMP_TO_EDGE) or 33648 (MIRRORED_REPEAT), got 9729"},
        BadQuad{"strength", {kUpright, {}, R"({"occlusionTexture": {"index": 0, "strength": 1.5}})", kPixelTexture},
                "materials[0].occlusionTexture.strength", "must be in [0, 1], got 1.5"},
        BadQuad{"emissive", {{}, {}, R"({"emissiveFactor": [0, 2.5, 0]})"}, "materials[0].emissiveFactor[1]",
                "must be in [0, 1], got 2.500000"},
        BadQuad{"zero-rotation", {{}, {}, "", "", R"({"mesh": 0, "rotation": [0, 0, 0, 0]})"}, "nodes[0].rotation",
                "must be a unit quaternion, but its length is 0.000000"},
        BadQuad{"long-rotation", {{}, {}, "", "", R"({"mesh": 0, "rotation": [0, 0, 0, 2]})"}, "nodes[0].rotation",
                "must be a unit quaternion, but its length is 2.000000"},
        BadQuad{"projective", {{}, {}, "", "", R"({"mesh": 0, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,0]})"},
                "nodes[0].matrix", "is not an affine transform: its last row must be 0, 0, 0, 1"},
        BadQuad{"alpha-mode", {{}, {}, R"({"alphaMode": "GLASS"})"}, "materials[0].alphaMode",
                "must be \"OPAQUE\", \"MASK\" or \"BLEND\", got \"GLASS\""},
        BadQuad{"alpha-cutoff", {{}, {}, R"({"alphaCutoff": -1})"}, "materials[0].alphaCutoff",
                "must be finite and >= 0"}),
    [](const ::testing::TestParamInfo<BadQuad>& p) {
        std::string n = p.param.name;
        std::replace(n.begin(), n.end(), '-', '_');
        return n;
    });

struct UvLayout {
    std::string name;
    std::vector<float> uvs;
    std::array<float, 4> tangent;  ///< expected at every corner: +U in world space, and w
};

void PrintTo(const UvLayout& layout, std::ostream* out) { *out << layout.name; }

class DerivedTangents : public ::testing::TestWithParam<UvLayout> {};

TEST_P(DerivedTangents, PointAlongPlusU) {
    const UvLayout& layout = GetParam();
    Diagnostics d;
    const auto quad = loadGltf(writeQuad("uv-" + layout.name, {layout.uvs}), {}, d);
    ASSERT_TRUE(quad) << messages(d);
    ASSERT_EQ(quad->vertices.size(), 4u);
    for (const MeshVertex& v : quad->vertices)
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(v.tangent[c], layout.tangent[size_t(c)], 1e-6) << c;
}

// glTF's bitangent, w * cross(normal, tangent), points up the image (towards v = 0, its first
// row), where a normal map's +Y points: upright, that is +Y, so w = +1.
INSTANTIATE_TEST_SUITE_P(
    Quads, DerivedTangents,
    ::testing::Values(UvLayout{"upright", kUpright, {1, 0, 0, 1}},
                      UvLayout{"turned", {0, 0, 0, 1, 1, 1, 1, 0}, {0, 1, 0, 1}},     // u = y, v = x
                      UvLayout{"mirrored", {1, 1, 0, 1, 0, 0, 1, 0}, {-1, 0, 0, -1}},  // u = 1 - x, v = 1 - y
                      UvLayout{"flipped", {0, 0, 1, 0, 1, 1, 0, 1}, {1, 0, 0, -1}},    // v = y: upside down
                      UvLayout{"none", {}, {1, 0, 0, 1}},                                // no UVs: any tangent
                      UvLayout{"degenerate", {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f}, {1, 0, 0, 1}}),
    [](const ::testing::TestParamInfo<UvLayout>& p) { return p.param.name; });

TEST(GltfTangents, AMirroringNodeTurnsTheBitangentOfFileAndDerivedTangentsAlike) {
    Quad withTangents{kUpright, {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1}};
    withTangents.node = R"({"mesh": 0, "scale": [-1, 1, 1]})";
    Quad derived = withTangents;
    derived.tangents.clear();
    Diagnostics d;
    const auto fromFile = loadGltf(writeQuad("mirrored-file-tangents", withTangents), {}, d);
    const auto fromUvs = loadGltf(writeQuad("mirrored-derived-tangents", derived), {}, d);
    ASSERT_TRUE(fromFile && fromUvs) << messages(d);
    for (const auto* mesh : {&*fromFile, &*fromUvs})
        for (const MeshVertex& v : mesh->vertices) {
            EXPECT_NEAR(v.tangent[0], -1.0f, 1e-6);  // +U, now towards -X
            EXPECT_EQ(v.tangent[3], -1.0f);          // the image still upright: its up is +Y = -cross(n, t)
        }
}

TEST(GltfTangents, AStretchingNodeCarriesTangentsAsDirections) {
    // A tangent along the diagonal, stretched twice along X: a direction along the surface goes
    // to (2, 1) (a normal, by the inverse transpose, would go to (0.5, 1)).
    const float r = float(std::sqrt(0.5));
    Quad q{kUpright, {r, r, 0, 1, r, r, 0, 1, r, r, 0, 1, r, r, 0, 1}};
    q.node = R"({"mesh": 0, "scale": [2, 1, 1]})";
    Diagnostics d;
    const auto quad = loadGltf(writeQuad("stretched-tangents", q), {}, d);
    ASSERT_TRUE(quad) << messages(d);
    for (const MeshVertex& v : quad->vertices) {
        EXPECT_NEAR(v.tangent[0], 2.0 / std::sqrt(5.0), 1e-6);
        EXPECT_NEAR(v.tangent[1], 1.0 / std::sqrt(5.0), 1e-6);
        EXPECT_NEAR(v.tangent[2], 0.0, 1e-6);
        EXPECT_EQ(v.tangent[3], 1.0f);
    }
}

TEST(GltfTangents, ANodeScaledToZeroStillGivesUnitNormalsAndTangents) {
    // Such a transform has no inverse transpose to carry normals. Flattened along Z, the quad
    // (at z = 0) is unchanged and faces +Z still; flattened along Y, or to a point, it is seen
    // edge-on, and any normal will do.
    for (const std::string scale : {"[1, 1, 0]", "[1, 0, 1]", "[0, 0, 0]"}) {
        Quad q{kUpright};
        q.node = R"({"mesh": 0, "scale": )" + scale + "}";
        Diagnostics d;
        const auto quad = loadGltf(writeQuad("scaled-to-zero", q), {}, d);
        ASSERT_TRUE(quad) << messages(d);
        for (const MeshVertex& v : quad->vertices) {
            EXPECT_NEAR(length3(v.normal), 1.0, 1e-6) << scale;
            if (scale == "[1, 1, 0]") {
                EXPECT_EQ(v.normal[2], 1.0f);
            }
        }
        expectTangentFrames(*quad);
    }
}

TEST(GltfTangents, TheFilesTangentsFollowItsNodesAndTheSceneTransform) {
    const fs::path cube = kModels / "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
    Diagnostics d;
    MeshTransform turned;
    turned.rotationDeg = {0.0, 90.0, 0.0};
    const auto still = loadGltf(cube, {}, d);
    const auto rotated = loadGltf(cube, turned, d);
    ASSERT_TRUE(still && rotated) << messages(d);
    ASSERT_EQ(still->vertices.size(), 24u);
    // The file's NORMAL (bytes 0 to 288 of its buffer) and TANGENT (from byte 288), turned by
    // its node's rotation, the quaternion (0, 0.7071067, -0.7071068, 0): half a turn.
    const std::string bin = fileBytes(cube.parent_path() / "AnimatedMorphCube.bin");
    const double q[3] = {0.0, 0.7071067, -0.7071068};  // w = 0: v' = (2 (q.v) q - (q.q) v) / (q.q)
    const double qq = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    size_t checked = 0;
    for (size_t i = 0; i < 24; ++i) {
        float n[3], t[4];
        std::memcpy(n, bin.data() + 12 * i, sizeof n);
        std::memcpy(t, bin.data() + 288 + 16 * i, sizeof t);
        if (std::abs(dot3(n, t)) > 0.5f) continue;  // the file's tangent is (1, 0, 0) on the faces facing X too
        ++checked;
        const double qt = q[0] * t[0] + q[1] * t[1] + q[2] * t[2];
        const MeshVertex& v = still->vertices[i];
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(v.tangent[c], (2 * qt * q[c] - qq * t[c]) / qq, 1e-5) << i;
        EXPECT_EQ(v.tangent[3], t[3]);
        // The scene's 90 degrees about +Y: (x, y, z) -> (z, y, -x).
        const MeshVertex& r = rotated->vertices[i];
        EXPECT_NEAR(r.tangent[0], v.tangent[2], 1e-6);
        EXPECT_NEAR(r.tangent[1], v.tangent[1], 1e-6);
        EXPECT_NEAR(r.tangent[2], -v.tangent[0], 1e-6);
        EXPECT_EQ(r.tangent[3], v.tangent[3]);
    }
    EXPECT_EQ(checked, 16u);
    expectTangentFrames(*still);  // the others too: any direction orthogonal to the normal
    expectTangentFrames(*rotated);
}

}  // namespace
}  // namespace skygraph
