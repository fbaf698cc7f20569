// Pixels on the host: what a Renderer reads back (readback(), readImage()) and uploads
// (setExternalImage()), and writing them to PNG, Radiance .hdr or OpenEXR files.
#pragma once

#include <skygraph/hdr_image.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace skygraph {

/// Pixels of one image, converted to linear-agnostic float RGBA (values as stored; sRGB
/// bytes are returned as byte/255, BGRA swizzled to RGBA). A plain value that owns its pixels.
struct ImageData {
    uint32_t width = 0;
    uint32_t height = 0;
    VkFormat format = VK_FORMAT_UNDEFINED;
    std::vector<float> rgba;  ///< width*height*4

    /// The pixel at (x, y), copied; x < width and y < height.
    [[nodiscard]] std::array<float, 4> pixel(uint32_t x, uint32_t y) const noexcept {
        const size_t i = (size_t(y) * width + x) * 4;
        return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
    }
};

/// The same pixels as an HdrImage (hdr_image.hpp's savers take one); a copy the caller owns.
[[nodiscard]] inline HdrImage toHdrImage(const ImageData& image) { return {image.width, image.height, image.rgba}; }

/// Writes 8-bit RGBA PNG (values clamped to [0,1]), through a temporary file renamed over
/// `path`, so a failure never leaves half a file there. Throws ImageError (hdr_image.hpp)
/// naming `path`, as hdr_image.hpp's savers do: on I/O failure or for an empty or malformed
/// image.
void writePng(const std::filesystem::path& path, const ImageData& image);
/// Writes an HDR file by extension: Radiance .hdr or OpenEXR .exr (half float), as atomically
/// as writePng (saveHdrImage). Throws ImageError naming `path` on I/O failure, for another
/// extension, or for an empty or malformed image.
void writeHdr(const std::filesystem::path& path, const ImageData& image);

}  // namespace skygraph
