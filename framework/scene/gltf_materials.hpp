// The materials of a glTF file and the images they sample, for gltf_loader.cpp. Reading a
// file keeps every image encoded; an image is decoded only once a drawn primitive's material
// uses it, so images that nothing draws cost neither time nor memory.
#pragma once

#include <skygraph/triangle_mesh.hpp>

#include <tiny_gltf.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace skygraph {

/// An image found unusable: where in the glTF (`images[N]`, or `images[N].uri` for an image
/// file) and what is wrong, naming the image file where there is one.
struct ImageProblem {
    std::string jsonPath;
    std::string message;
};

/// checkImageHeader's user data: the model tinygltf is filling (its buffers are read before
/// its images), the glTF file's folder (which image uris are relative to), and each image found
/// unusable, by index. The loader reports those with their JSON paths, which tinygltf's own
/// error text would lack.
struct ImageHeaderCheck {
    const tinygltf::Model* model = nullptr;
    size_t maxTextureSide = 0;
    std::filesystem::path baseDir;
    std::map<int, ImageProblem> problems;
};

/// Where images[index] is reported and how its problem is said: at its `uri` with the image
/// file (resolved against `baseDir`) named for an image in a file of its own, else at the image.
[[nodiscard]] ImageProblem imageProblem(const tinygltf::Image& image, size_t index,
                                        const std::filesystem::path& baseDir, const std::string& problem);

/// tinygltf's image callback (`headerCheck`: an ImageHeaderCheck). Checks the header with stb
/// (a format stb decodes, at most `maxTextureSide` texels a side) and an image's buffer view
/// against its buffer, which tinygltf leaves unchecked, then keeps the encoded bytes in
/// `image->image` (`as_is`). A problem is recorded rather than returned, so that tinygltf
/// reads on and every bad image is named.
bool checkImageHeader(tinygltf::Image* image, int index, std::string* error, std::string* warning, int requestedWidth,
                      int requestedHeight, const unsigned char* bytes, int size, void* headerCheck);

/// Receives each problem: the JSON path in the file and what is wrong.
using GltfError = std::function<void(const std::string& path, const std::string& message)>;

/// The materials of one file's drawn primitives, each image decoded at most once.
class GltfMaterials {
public:
    /// Decodes images while their RGBA8 bytes stay within `maxImageBytes` in all; `baseDir`:
    /// the glTF file's folder, which image uris are relative to.
    GltfMaterials(const tinygltf::Model& model, std::filesystem::path baseDir, size_t maxImageBytes, GltfError error);

    /// materials[index] (glTF's default material for -1), checked. Its textures' `image` are
    /// still the file's image indices: use() turns them into TriangleMesh::images indices, once
    /// the primitive is known to be drawn.
    MeshMaterial read(int index, const std::string& reference);

    /// Decodes the images `material` (from read()) samples that are not in `images` yet, appends
    /// them, and points its textures at them. An image that cannot be decoded is an error.
    void use(MeshMaterial& material, std::vector<MeshImage>& images);

private:
    MeshTexture texture(int index, int texCoord, const std::string& key);
    MeshWrap wrap(int mode, const std::string& path);
    int32_t decode(size_t fileImage, std::vector<MeshImage>& images);

    /// Why `image`, whose uri names a file, has no bytes: tinygltf only warns when it cannot read one.
    std::string unreadFileProblem(const tinygltf::Image& image) const;

    const tinygltf::Model& model_;
    std::filesystem::path baseDir_;
    size_t maxImageBytes_;
    GltfError error_;
    /// By the file's image index: where it is in TriangleMesh::images, or -1 (not decoded yet),
    /// or -2 (it could not be, and that was reported).
    std::vector<int32_t> meshImageOf_;
    size_t decodedBytes_ = 0;
};

/// True when the material samples any texture, so its primitive needs TEXCOORD_0.
[[nodiscard]] bool samplesTextures(const MeshMaterial& material);

}  // namespace skygraph
