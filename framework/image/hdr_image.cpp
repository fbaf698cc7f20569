// Dispatch by extension, the error type, and the checks shared by both formats.
#include "image_internal.hpp"

#include "file_extension.hpp"
#include "printable_name.hpp"
#include "replace_file.hpp"

#include <algorithm>
#include <cmath>

namespace skygraph {

ImageError::ImageError(const std::filesystem::path& file, const std::string& reason)
    : std::runtime_error(printableName("'" + file.string() + "': " + reason)), file_(file) {}

HdrImage loadHdrImage(const std::filesystem::path& path) {
    const std::string ext = lowercaseExtension(path);
    if (ext == ".hdr") return loadRadianceHdr(path);
    if (ext == ".exr") return loadExr(path);
    throw ImageError(path, "unknown image extension '" + ext + "'; expected .hdr or .exr");
}

void saveHdrImage(const std::filesystem::path& path, const HdrImage& image) {
    image_detail::writeBytes(path, encodeHdrImage(path, image));
}

std::string encodeHdrImage(const std::filesystem::path& path, const HdrImage& image) {
    const std::string ext = lowercaseExtension(path);
    if (ext == ".hdr") return image_detail::encodeRadianceHdr(path, image);
    if (ext == ".exr") return image_detail::encodeExr(path, image);
    throw ImageError(path, "unknown image extension '" + ext + "'; expected .hdr or .exr");
}

size_t countNonFinite(const HdrImage& image) noexcept {
    return static_cast<size_t>(std::count_if(image.rgba.begin(), image.rgba.end(),
                                             [](float v) { return !std::isfinite(v); }));
}

namespace image_detail {

void requireReadableFile(const std::filesystem::path& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(status)) throw ImageError(path, "no such file");
    if (!std::filesystem::is_regular_file(status)) throw ImageError(path, "not a regular file");
}

std::string sniffFormat(std::string_view b) {
    if (b.starts_with("\x89PNG\r\n\x1a\n")) return "a PNG image";
    if (b.starts_with("\xff\xd8\xff")) return "a JPEG image";
    if (b.starts_with("\x76\x2f\x31\x01")) return "an OpenEXR image";
    if (b.starts_with("#?RADIANCE") || b.starts_with("#?RGBE")) return "a Radiance HDR image";
    if (b.starts_with("GIF8")) return "a GIF image";
    if (b.starts_with("BM")) return "a BMP image";
    return "";
}

void requireLoadableSize(const std::filesystem::path& path, int64_t width, int64_t height) {
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    if (width == 0 || height == 0) throw ImageError(path, "zero size (the header says " + size + ")");
    // A size past 32 bits reads as negative.
    if (width < 0 || height < 0) throw ImageError(path, "corrupt header: its size reads as " + size);
    if (width > kMaxHdrImageWidth || height > kMaxHdrImageHeight)
        throw ImageError(path, "size " + size + " exceeds the limit " + std::to_string(kMaxHdrImageWidth) +
                                   "x" + std::to_string(kMaxHdrImageHeight));
}

void requireWritable(const std::filesystem::path& path, const HdrImage& image) {
    if (image.width == 0 || image.height == 0)
        throw ImageError(path, "cannot write an image of zero size");
    if (image.width > kMaxHdrImageWidth || image.height > kMaxHdrImageHeight)
        throw ImageError(path, "cannot write " + std::to_string(image.width) + "x" +
                                   std::to_string(image.height) + "; the limit is " +
                                   std::to_string(kMaxHdrImageWidth) + "x" +
                                   std::to_string(kMaxHdrImageHeight));
    if (image.rgba.size() != size_t(image.width) * image.height * 4)
        throw ImageError(path, "image has " + std::to_string(image.rgba.size()) +
                                   " floats; width*height*4 would be " +
                                   std::to_string(size_t(image.width) * image.height * 4));
}

void writeBytes(const std::filesystem::path& path, std::string_view bytes) {
    try {
        files::replaceFileContents(path, bytes);
    } catch (const std::filesystem::filesystem_error& e) {
        throw ImageError(path, "cannot write: " + files::whyNotWritten(e));
    }
}

void appendToString(void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<size_t>(size));
}

}  // namespace image_detail
}  // namespace skygraph
