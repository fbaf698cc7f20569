// GltfMaterials and checkImageHeader: see gltf_materials.hpp. stb decodes every image to 8-bit
// RGBA whatever the file holds (16-bit PNGs included), since MeshImage has that one format.
#include "gltf_materials.hpp"

#include "gltf_json_types.hpp"

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <system_error>
#include <utility>

namespace skygraph {
namespace {

constexpr int32_t kNotDecoded = -1;
constexpr int32_t kUndecodable = -2;

std::string at(const char* array, size_t i) { return std::string(array) + "[" + std::to_string(i) + "]"; }

std::string stbReason() {
    const char* reason = stbi_failure_reason();
    return reason ? reason : "no reason given";
}

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr unsigned char kJpegSignature[3] = {0xff, 0xd8, 0xff};

bool startsWith(std::span<const unsigned char> data, std::span<const unsigned char> signature) {
    return data.size() >= signature.size() && std::equal(signature.begin(), signature.end(), data.begin());
}

/// glTF 2.0's images are PNG or JPEG. stb reads more (Radiance, PNM, GIF, PSD...), and the
/// Debian stb's readers of those hang on a zero run length, read past a 16-bit PNM's pixels,
/// and fill a cut-short GIF without a word: none of them is let near it.
std::string notPngOrJpeg(std::span<const unsigned char> data) {
    if (startsWith(data, kPngSignature) || startsWith(data, kJpegSignature)) return {};
    return "is neither a PNG nor a JPEG file (a glTF 2.0 image is one or the other)";
}

/// Why a JPEG's bytes are too few for its size, or empty: every 8x8 block of the full-size
/// component takes at least one bit (its DC difference's code, in a baseline or a progressive
/// first scan), and stb fills missing coded data with zeros, so a file of a hundred bytes
/// would decode to a 16384x16384 image of nothing, gigabytes of it.
std::string jpegTooShort(std::span<const unsigned char> data, uint64_t width, uint64_t height) {
    if (!startsWith(data, kJpegSignature)) return {};
    const uint64_t blocks = ((width + 7) / 8) * ((height + 7) / 8);
    const uint64_t fewest = (blocks + 7) / 8;
    if (data.size() >= fewest) return {};
    return "is a JPEG of " + std::to_string(width) + "x" + std::to_string(height) + ", whose " +
           std::to_string(blocks) + " blocks take at least " + std::to_string(fewest) + " bytes, but it has " +
           std::to_string(data.size()) + ": it is cut short";
}

/// Why a PNG's chunks cannot all be in `data`, or empty (also for data that is no PNG): stb
/// grows its buffer for the compressed pixels to a chunk's declared length before reading it,
/// so a forged length would allocate up to 2 GiB for a file of a few bytes.
std::string pngChunkProblem(std::span<const unsigned char> data) {
    if (!startsWith(data, kPngSignature)) return {};
    for (size_t at = 8; at + 8 <= data.size();) {
        const uint64_t length = uint64_t(data[at]) << 24 | uint64_t(data[at + 1]) << 16 | uint64_t(data[at + 2]) << 8 |
                                uint64_t(data[at + 3]);
        const uint64_t end = uint64_t(at) + 12 + length;  // length, type, data, CRC
        if (end > data.size())
            return "a PNG chunk at byte " + std::to_string(at) + " declares " + std::to_string(length) +
                   " bytes, past the end of the image's " + std::to_string(data.size());
        at = size_t(end);
    }
    return {};
}

/// A PNG's width and height from its header chunk, or {0, 0} for data that is no PNG. stb's
/// own reading refuses a PNG of more than 2^30 decoded bytes as unreadable, so the size
/// limit is checked on these first.
std::pair<uint64_t, uint64_t> pngHeaderSize(std::span<const unsigned char> data) {
    static constexpr unsigned char kStart[16] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
    if (data.size() < 24 || !std::equal(kStart, kStart + 16, data.begin())) return {0, 0};
    const auto bigEndian = [&](size_t at) {
        return uint64_t(data[at]) << 24 | uint64_t(data[at + 1]) << 16 | uint64_t(data[at + 2]) << 8 | data[at + 3];
    };
    return {bigEndian(16), bigEndian(20)};
}

}  // namespace

ImageProblem imageProblem(const tinygltf::Image& image, size_t index, const std::filesystem::path& baseDir,
                          const std::string& problem) {
    const std::string path = at("images", index);
    // tinygltf keeps the uri of an image file only, not a data URI.
    if (image.uri.empty() || image.bufferView >= 0) return {path, problem};
    return {path + ".uri", "image file '" + uriFile(baseDir, image.uri).string() + "': " + problem};
}

bool checkImageHeader(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                      const unsigned char* bytes, const int size, void* headerCheck) {
    auto& check = *static_cast<ImageHeaderCheck*>(headerCheck);
    const auto problem = [&](const std::string& message) {
        check.problems.emplace(index, imageProblem(*image, size_t(index), check.baseDir, message));
        return true;
    };
    if (image->bufferView >= 0) {  // tinygltf passes the view's bytes without checking them against the buffer
        const tinygltf::BufferView& view = check.model->bufferViews[size_t(image->bufferView)];
        const size_t bufferBytes = check.model->buffers[size_t(view.buffer)].data.size();
        if (view.byteOffset > bufferBytes || view.byteLength > bufferBytes - view.byteOffset)
            return problem("its buffer view, bufferViews[" + std::to_string(image->bufferView) +
                           "], lies outside buffer " + std::to_string(view.buffer) + " of " +
                           std::to_string(bufferBytes) + " bytes");
    }
    if (size <= 0) return problem("has no bytes, or more than 2 GiB");
    const std::span<const unsigned char> data(bytes, size_t(size));
    if (const std::string why = notPngOrJpeg(data); !why.empty()) return problem(why);
    const auto tooLarge = [&](uint64_t width, uint64_t height) {
        return (width > check.maxTextureSide || height > check.maxTextureSide) &&
               problem(std::to_string(width) + "x" + std::to_string(height) + " is larger than " +
                       std::to_string(check.maxTextureSide) + " texels a side");
    };
    if (const auto [pngWidth, pngHeight] = pngHeaderSize({bytes, size_t(size)}); tooLarge(pngWidth, pngHeight))
        return true;
    int width = 0, height = 0, components = 0;
    if (!stbi_info_from_memory(bytes, size, &width, &height, &components))
        return problem("not an image stb can read (" + stbReason() + ")");
    if (tooLarge(uint64_t(width), uint64_t(height))) return true;
    if (const std::string why = jpegTooShort(data, uint64_t(width), uint64_t(height)); !why.empty()) return problem(why);
    image->width = width;
    image->height = height;
    image->component = components;
    image->image.assign(bytes, bytes + size);
    image->as_is = true;  // tinygltf's marker for bytes kept encoded
    return true;
}

bool samplesTextures(const MeshMaterial& m) {
    return m.baseColorTexture.present() || m.metallicRoughnessTexture.present() || m.normalTexture.present() ||
           m.occlusionTexture.present() || m.emissiveTexture.present();
}

GltfMaterials::GltfMaterials(const tinygltf::Model& model, std::filesystem::path baseDir, size_t maxImageBytes,
                             GltfError error)
    : model_(model),
      baseDir_(std::move(baseDir)),
      maxImageBytes_(maxImageBytes),
      error_(std::move(error)),
      meshImageOf_(model.images.size(), kNotDecoded) {}

MeshMaterial GltfMaterials::read(int index, const std::string& reference) {
    MeshMaterial m;
    if (index < 0) return m;  // glTF's default material
    if (size_t(index) >= model_.materials.size())
        return error_(reference, "material " + std::to_string(index) + " does not exist"), m;
    const tinygltf::Material& mat = model_.materials[size_t(index)];
    const std::string mpath = at("materials", size_t(index));
    const auto& pbr = mat.pbrMetallicRoughness;
    const auto unit = [&](double v, const std::string& key) {
        if (!(v >= 0.0 && v <= 1.0)) error_(mpath + "." + key, "must be in [0, 1], got " + std::to_string(v));
        return std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 1.0);
    };
    if (pbr.baseColorFactor.size() == 4)
        for (int c = 0; c < 4; ++c)
            m.baseColor[size_t(c)] =
                unit(pbr.baseColorFactor[size_t(c)], "pbrMetallicRoughness.baseColorFactor[" + std::to_string(c) + "]");
    m.metallic = unit(pbr.metallicFactor, "pbrMetallicRoughness.metallicFactor");
    m.roughness = unit(pbr.roughnessFactor, "pbrMetallicRoughness.roughnessFactor");
    // glTF bounds it to [0, 1] (brighter takes KHR_materials_emissive_strength, which skygraph
    // does not read): a larger value would pass for the file's intent, and past a float's
    // range shade infinity.
    if (mat.emissiveFactor.size() == 3)
        for (int c = 0; c < 3; ++c)
            m.emissive[size_t(c)] = unit(mat.emissiveFactor[size_t(c)], "emissiveFactor[" + std::to_string(c) + "]");
    const auto textureOf = [&](const auto& info, const std::string& key) {
        return texture(info.index, info.texCoord, mpath + key);
    };
    m.baseColorTexture = textureOf(pbr.baseColorTexture, ".pbrMetallicRoughness.baseColorTexture");
    m.metallicRoughnessTexture =
        textureOf(pbr.metallicRoughnessTexture, ".pbrMetallicRoughness.metallicRoughnessTexture");
    m.normalTexture = textureOf(mat.normalTexture, ".normalTexture");
    m.occlusionTexture = textureOf(mat.occlusionTexture, ".occlusionTexture");
    m.emissiveTexture = textureOf(mat.emissiveTexture, ".emissiveTexture");
    if (!std::isfinite(mat.normalTexture.scale)) error_(mpath + ".normalTexture.scale", "must be finite");
    else m.normalScale = mat.normalTexture.scale;
    m.occlusionStrength = unit(mat.occlusionTexture.strength, "occlusionTexture.strength");
    if (mat.alphaMode == "OPAQUE") m.alphaMode = MeshAlphaMode::Opaque;
    else if (mat.alphaMode == "MASK") m.alphaMode = MeshAlphaMode::Mask;
    else if (mat.alphaMode == "BLEND") m.alphaMode = MeshAlphaMode::Blend;
    else error_(mpath + ".alphaMode", "must be \"OPAQUE\", \"MASK\" or \"BLEND\", got \"" + mat.alphaMode + "\"");
    if (!(mat.alphaCutoff >= 0.0) || !std::isfinite(mat.alphaCutoff))
        error_(mpath + ".alphaCutoff", "must be finite and >= 0, got " + std::to_string(mat.alphaCutoff));
    else m.alphaCutoff = mat.alphaCutoff;
    m.doubleSided = mat.doubleSided;
    return m;
}

MeshTexture GltfMaterials::texture(int index, int texCoord, const std::string& key) {
    MeshTexture t;
    if (index < 0) return t;
    if (size_t(index) >= model_.textures.size())
        return error_(key + ".index", "texture " + std::to_string(index) + " does not exist"), t;
    if (texCoord != 0)
        error_(key + ".texCoord",
               "TEXCOORD_" + std::to_string(texCoord) + " is not supported: skygraph reads TEXCOORD_0 only");
    const tinygltf::Texture& gltfTexture = model_.textures[size_t(index)];
    const std::string path = at("textures", size_t(index));
    if (gltfTexture.source < 0)
        return error_(path + ".source", "is missing (" + key + " samples the texture); an image that only an "
                                            "extension names is not supported"), t;
    if (size_t(gltfTexture.source) >= model_.images.size())
        return error_(path + ".source", "image " + std::to_string(gltfTexture.source) + " does not exist"), t;
    if (const int s = gltfTexture.sampler; s >= 0) {  // else glTF's default: repeat both ways
        if (size_t(s) >= model_.samplers.size())
            return error_(path + ".sampler", "sampler " + std::to_string(s) + " does not exist"), t;
        t.wrapS = wrap(model_.samplers[size_t(s)].wrapS, at("samplers", size_t(s)) + ".wrapS");
        t.wrapT = wrap(model_.samplers[size_t(s)].wrapT, at("samplers", size_t(s)) + ".wrapT");
    }
    t.image = gltfTexture.source;
    return t;
}

MeshWrap GltfMaterials::wrap(int mode, const std::string& path) {
    switch (mode) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT: return MeshWrap::Repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return MeshWrap::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return MeshWrap::MirroredRepeat;
        default:
            error_(path, "must be 10497 (REPEAT), 33071 (CLAMP_TO_EDGE) or 33648 (MIRRORED_REPEAT), got " +
                             std::to_string(mode));
            return MeshWrap::Repeat;
    }
}

void GltfMaterials::use(MeshMaterial& m, std::vector<MeshImage>& images) {
    for (MeshTexture* t : {&m.baseColorTexture, &m.metallicRoughnessTexture, &m.normalTexture, &m.occlusionTexture,
                           &m.emissiveTexture})
        if (t->present()) t->image = decode(size_t(t->image), images);
}

int32_t GltfMaterials::decode(size_t fileImage, std::vector<MeshImage>& images) {
    int32_t& meshImage = meshImageOf_[fileImage];
    if (meshImage != kNotDecoded) return std::max(meshImage, int32_t(-1));
    meshImage = kUndecodable;  // until it is
    const tinygltf::Image& image = model_.images[fileImage];
    const std::string path = at("images", fileImage);
    const auto fileError = [&](const std::string& problem) {
        const ImageProblem where = imageProblem(image, fileImage, baseDir_, problem);
        error_(where.jsonPath, where.message);
        return -1;
    };
    if (image.image.empty()) {  // tinygltf only warns when an image's file cannot be read
        if (image.uri.empty()) return error_(path, "has no data"), -1;
        return fileError(unreadFileProblem(image));
    }
    const size_t bytes = size_t(image.width) * size_t(image.height) * 4;
    // Checked before stb runs: it takes a buffer of the header's size before reading any pixel.
    if (decodedBytes_ + bytes > maxImageBytes_)
        return error_(path, "decoded, the file's images would take " + std::to_string(decodedBytes_ + bytes) +
                                " bytes, more than " + std::to_string(maxImageBytes_)), -1;
    if (const std::string problem = pngChunkProblem(image.image); !problem.empty())
        return fileError("cannot be decoded (" + problem + ")");
    int width = 0, height = 0, components = 0;
    const std::unique_ptr<stbi_uc, void (*)(void*)> rgba(
        stbi_load_from_memory(image.image.data(), int(image.image.size()), &width, &height, &components, 4),
        stbi_image_free);
    if (!rgba) return fileError("cannot be decoded (" + stbReason() + ")");
    if (width != image.width || height != image.height)  // the header promised otherwise: a hostile file
        return fileError("decodes to " + std::to_string(width) + "x" + std::to_string(height) + ", not the header's " +
                         std::to_string(image.width) + "x" + std::to_string(image.height));
    MeshImage decoded;
    decoded.width = uint32_t(width);
    decoded.height = uint32_t(height);
    decoded.rgba.assign(rgba.get(), rgba.get() + bytes);
    decoded.name = path;
    decodedBytes_ += bytes;
    images.push_back(std::move(decoded));
    meshImage = int32_t(images.size() - 1);
    return meshImage;
}

std::string GltfMaterials::unreadFileProblem(const tinygltf::Image& image) const {
    const std::filesystem::path file = uriFile(baseDir_, image.uri);
    if (std::string why = notARegularFile(file); !why.empty()) return why;
    std::error_code ec;
    if (std::filesystem::file_size(file, ec) == 0 && !ec) return "is empty";
    return "cannot be read";
}

}  // namespace skygraph
