// PNG and Radiance HDR output through stb_image_write.
#include <skygraph/image_data.hpp>

// stb's implementation lives in skygraph_image (its only owner).
#include <skygraph/hdr_image.hpp>

#include "image_internal.hpp"

#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>

namespace skygraph {
namespace {

void checkImage(const std::filesystem::path& path, const ImageData& image) {
    if (image.width == 0 || image.height == 0 || image.rgba.size() != size_t(image.width) * image.height * 4)
        throw ImageError(path, "the image to write is empty or malformed");
}

}  // namespace

void writePng(const std::filesystem::path& path, const ImageData& image) {
    checkImage(path, image);
    std::vector<uint8_t> bytes(image.rgba.size());
    for (size_t i = 0; i < bytes.size(); ++i) {
        bytes[i] = static_cast<uint8_t>(std::lround(std::clamp(image.rgba[i], 0.0f, 1.0f) * 255.0f));
    }
    // Nothing half-written under the final name, and no temporary left behind.
    std::string encoded;
    if (!stbi_write_png_to_func(image_detail::appendToString, &encoded, static_cast<int>(image.width),
                                static_cast<int>(image.height), 4, bytes.data(), static_cast<int>(image.width * 4)))
        throw ImageError(path, "cannot encode the image");
    image_detail::writeBytes(path, encoded);
}

void writeHdr(const std::filesystem::path& path, const ImageData& image) {
    checkImage(path, image);
    saveHdrImage(path, toHdrImage(image));  // by extension: .hdr (Radiance) or .exr (half float)
}

}  // namespace skygraph
