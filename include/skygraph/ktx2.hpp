// KTX 2.0 output (Khronos Texture Container):
// float textures with mip levels, 2D or cube, uncompressed, no supercompression: the subset
// the environment pipeline writes, with no KTX library to link. The files are standard
// KTX 2.0.
#pragma once

#include <skygraph/hdr_image.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace skygraph {

/// Texel formats the writer knows, by their VkFormat value (kept as plain numbers so this
/// header needs no Vulkan).
enum class Ktx2Format : uint32_t {
    Rgba16Float = 97,   ///< VK_FORMAT_R16G16B16A16_SFLOAT
    Rgba32Float = 109,  ///< VK_FORMAT_R32G32B32A32_SFLOAT
    Rg16Float = 83,     ///< VK_FORMAT_R16G16_SFLOAT (R and G of each pixel)
    Rg32Float = 103,    ///< VK_FORMAT_R32G32_SFLOAT
};

/// A texture to write: levels[mip][face], mip 0 first; 1 face (2D) or 6 (cube, in Vulkan
/// order +X,-X,+Y,-Y,+Z,-Z). Level m must be max(1, width >> m) by max(1, height >> m).
/// Rows top to bottom (KTXorientation "rd"). A plain value; owns its pixels.
struct Ktx2Texture {
    Ktx2Format format = Ktx2Format::Rgba16Float;
    std::vector<std::vector<HdrImage>> levels;
};

/// Writes `texture` to `path`: into a temporary file beside it, renamed over `path` only once
/// complete. Floats are rounded to the nearest half for the 16-bit formats. Throws ImageError
/// for an inconsistent texture (sizes, face count) or an I/O failure; never leaves half a file.
void saveKtx2(const std::filesystem::path& path, const Ktx2Texture& texture);

/// The bytes saveKtx2() writes, in memory, for a caller that writes the file itself (several
/// files replaced together, say). `path` names the file in errors only. Throws ImageError for
/// an inconsistent texture.
[[nodiscard]] std::string encodeKtx2(const std::filesystem::path& path, const Ktx2Texture& texture);

}  // namespace skygraph
