// Radiance RGBE (.hdr) through stb_image and stb_image_write.
//
// stb_image reads zeros past the end of its input and, given a zero run count, spins forever on
// the same scanline, so a truncated or damaged run-length stream would hang it. Before decoding,
// checkRgbeStream() walks the stream's structure the way stb will read it (without decoding
// pixels) and rejects it unless every byte stb will ask for is there and every count advances.
#include "image_internal.hpp"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <climits>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <string_view>
#include <vector>

namespace skygraph {
namespace {

using image_detail::sniffFormat;

/// Offset of the first pixel byte: after the signature line, the header lines up to the one
/// that ends it, and the resolution line. Returns the file size when the header is not
/// terminated.
size_t rgbeDataOffset(const std::string& bytes) {
    size_t pos = 0;
    bool headerEnded = false;
    for (int line = 0; pos < bytes.size(); ++line) {
        const size_t end = bytes.find('\n', pos);
        if (end == std::string::npos) return bytes.size();
        // stb_image (stbi__hdr_load) keeps each line as a C string and ends the header at the
        // first empty one, so a line that starts with NUL ends it too. Ending it anywhere else
        // would check one stream and let stb decode another.
        const bool empty = end == pos || bytes[pos] == '\0';
        pos = end + 1;
        if (headerEnded) return pos;  // that was the resolution line
        headerEnded = line > 0 && empty;
    }
    return bytes.size();
}

/// The values of the header's FORMAT= lines, read as stb_image reads the header: each line
/// after the signature up to the first empty one (or one that starts with NUL), whole.
std::vector<std::string> headerFormats(const std::string& bytes) {
    std::vector<std::string> formats;
    for (size_t pos = bytes.find('\n'); pos != std::string::npos && ++pos < bytes.size();) {
        const size_t end = bytes.find('\n', pos);
        const std::string_view line = std::string_view(bytes).substr(pos, end == std::string::npos ? end : end - pos);
        if (line.empty() || line.front() == '\0') break;
        if (line.starts_with("FORMAT=")) formats.emplace_back(line.substr(std::strlen("FORMAT=")));
        pos = end;
    }
    return formats;
}

void checkRgbeStream(const std::filesystem::path& path, const std::string& bytes, size_t p,
                     size_t w, size_t h) {
    const size_t size = bytes.size();
    auto byte = [&](size_t i) { return static_cast<unsigned char>(bytes[i]); };
    auto truncated = [&](size_t row) {
        return ImageError(path, "truncated: the pixel data ends in row " + std::to_string(row) +
                                    " of " + std::to_string(h));
    };
    // stb reads w*h*4 bytes from `from`: pixels without run-length encoding fill the image
    // from its first row again, wherever they start.
    auto needFlat = [&](size_t from) {
        if (size - from < w * h * 4) throw truncated((size - from) / (w * 4));
    };
    if (w < 8 || w >= 32768) return needFlat(p);
    for (size_t row = 0; row < h; ++row) {
        if (size - p < 4) throw truncated(row);
        if (byte(p) != 2 || byte(p + 1) != 2 || (byte(p + 2) & 0x80)) return needFlat(p);
        if ((size_t(byte(p + 2)) << 8 | byte(p + 3)) != w)
            throw ImageError(path, "corrupt data: row " + std::to_string(row) +
                                       " has a wrong run-length scanline width");
        p += 4;
        for (int channel = 0; channel < 4; ++channel) {
            for (size_t x = 0; x < w;) {
                if (p >= size) throw truncated(row);
                const size_t count = byte(p++);
                const size_t n = count > 128 ? count - 128 : count;
                if (n == 0 || n > w - x)
                    throw ImageError(path, "corrupt data: bad run length in row " + std::to_string(row));
                const size_t payload = count > 128 ? 1 : n;
                if (size - p < payload) throw truncated(row);
                p += payload;
                x += n;
            }
        }
    }
}

std::string readWholeFile(const std::filesystem::path& path) {
    image_detail::requireReadableFile(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ImageError(path, "cannot open for reading");
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw ImageError(path, "read error");
    return bytes;
}

}  // namespace

HdrImage loadRadianceHdr(const std::filesystem::path& path) {
    const std::string bytes = readWholeFile(path);
    if (bytes.empty()) throw ImageError(path, "empty file; expected a Radiance HDR image");
    if (bytes.size() > size_t(INT_MAX)) throw ImageError(path, "over 2 GiB; stb_image cannot read it");
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int len = static_cast<int>(bytes.size());
    if (!stbi_is_hdr_from_memory(data, len)) {
        const std::string kind = sniffFormat(bytes);
        if (kind == "a Radiance HDR image")  // the signature, but not on a line of its own
            throw ImageError(path, "corrupt header: its #?RADIANCE or #?RGBE signature must end its line with a "
                                   "newline alone (this one is followed by other bytes, e.g. CR LF line ends)");
        throw ImageError(path, "not a Radiance HDR image (" +
                                   (kind.empty() ? "no #?RADIANCE or #?RGBE signature" : "it is " + kind) + ")");
    }
    // stb_image reads only FORMAT=32-bit_rle_rgbe and calls any other header unknown.
    if (const std::vector<std::string> formats = headerFormats(bytes);
        !formats.empty() && std::find(formats.begin(), formats.end(), "32-bit_rle_rgbe") == formats.end()) {
        if (std::find(formats.begin(), formats.end(), "32-bit_rle_xyze") != formats.end())
            throw ImageError(path, "XYZE .hdr files (FORMAT=32-bit_rle_xyze) are not supported; only "
                                   "FORMAT=32-bit_rle_rgbe is");
        const std::string& format = formats.front();
        const std::string shown = format.size() > 40 ? format.substr(0, 40) + "..." : format;
        throw ImageError(path, "unknown pixel format FORMAT=" + shown + "; expected FORMAT=32-bit_rle_rgbe");
    }
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(data, len, &w, &h, &comp))
        throw ImageError(path, std::string("corrupt or truncated header: ") + stbi_failure_reason());
    image_detail::requireLoadableSize(path, w, h);
    if (size_t(w) * size_t(h) * 3 * sizeof(float) > size_t(INT_MAX))
        throw ImageError(path, "size " + std::to_string(w) + "x" + std::to_string(h) +
                                   " is over stb_image's 2 GiB decode limit for .hdr; use .exr");
    checkRgbeStream(path, bytes, rgbeDataOffset(bytes), size_t(w), size_t(h));

    std::unique_ptr<float, void (*)(void*)> rgb(stbi_loadf_from_memory(data, len, &w, &h, &comp, 3),
                                                stbi_image_free);
    if (!rgb) throw ImageError(path, std::string("cannot decode: ") + stbi_failure_reason());
    HdrImage image{uint32_t(w), uint32_t(h), {}};
    image.rgba.resize(size_t(w) * size_t(h) * 4);
    for (size_t i = 0, n = size_t(w) * size_t(h); i < n; ++i) {
        for (size_t c = 0; c < 3; ++c) image.rgba[i * 4 + c] = rgb.get()[i * 3 + c];
        image.rgba[i * 4 + 3] = 1.0f;
    }
    return image;
}

namespace image_detail {

std::string encodeRadianceHdr(const std::filesystem::path& path, const HdrImage& image) {
    requireWritable(path, image);
    std::vector<float> rgb(size_t(image.width) * image.height * 3);
    for (size_t i = 0; i < size_t(image.width) * image.height; ++i)
        for (size_t c = 0; c < 3; ++c) rgb[i * 3 + c] = image.rgba[i * 4 + c];
    std::string encoded;
    if (!stbi_write_hdr_to_func(appendToString, &encoded, int(image.width), int(image.height), 3, rgb.data()))
        throw ImageError(path, "cannot encode the image");
    return encoded;
}

}  // namespace image_detail

void saveRadianceHdr(const std::filesystem::path& path, const HdrImage& image) {
    image_detail::writeBytes(path, image_detail::encodeRadianceHdr(path, image));
}

}  // namespace skygraph
