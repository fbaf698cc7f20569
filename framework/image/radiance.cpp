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
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

namespace skygraph {
namespace {

using image_detail::sniffFormat;

/// Where the resolution line starts: after the signature line and the header lines up to the
/// one that ends it. The file size when the header is not terminated.
size_t resolutionLineOffset(const std::string& bytes) {
    size_t pos = 0;
    for (int line = 0; pos < bytes.size(); ++line) {
        const size_t end = bytes.find('\n', pos);
        if (end == std::string::npos) return bytes.size();
        // stb_image (stbi__hdr_load) keeps each line as a C string and ends the header at the
        // first empty one, so a line that starts with NUL ends it too. Ending it anywhere else
        // would check one stream and let stb decode another.
        const bool empty = end == pos || bytes[pos] == '\0';
        pos = end + 1;
        if (line > 0 && empty) return pos;
    }
    return bytes.size();
}

/// Offset of the first pixel byte: after the resolution line.
size_t rgbeDataOffset(const std::string& bytes) {
    const size_t end = bytes.find('\n', resolutionLineOffset(bytes));
    return end == std::string::npos ? bytes.size() : end + 1;
}

/// What the header says beyond the pixels, read as stb_image reads it: each line after the
/// signature up to the first empty one (or one that starts with NUL), whole.
struct RadianceHeader {
    std::vector<std::string> formats;  ///< FORMAT= values
    /// The product of every EXPOSURE= and COLORCORR= (per channel) value: Radiance's file
    /// format says both are cumulative multipliers already applied to the pixels, which are
    /// divided by them to give radiance.
    double multiplier[3] = {1.0, 1.0, 1.0};
};

/// One positive finite number per value of a header line's `line` (after its `key`).
std::vector<double> headerNumbers(const std::filesystem::path& path, std::string_view line, std::string_view key,
                                  size_t count) {
    std::vector<double> values;
    std::string text(line.substr(key.size()));
    const char* at = text.c_str();
    for (size_t i = 0; i < count; ++i) {
        char* end = nullptr;
        const double v = std::strtod(at, &end);
        if (end == at || !std::isfinite(v) || v <= 0.0) {
            const std::string shown = line.size() > 60 ? std::string(line.substr(0, 60)) + "..." : std::string(line);
            throw ImageError(path, "corrupt header line '" + shown + "': " + std::string(key) + " takes " +
                                       (count == 1 ? "a positive number" : std::to_string(count) + " positive numbers"));
        }
        values.push_back(v);
        at = end;
    }
    return values;
}

RadianceHeader readHeader(const std::filesystem::path& path, const std::string& bytes) {
    RadianceHeader header;
    for (size_t pos = bytes.find('\n'); pos != std::string::npos && ++pos < bytes.size();) {
        const size_t end = bytes.find('\n', pos);
        const std::string_view line = std::string_view(bytes).substr(pos, end == std::string::npos ? end : end - pos);
        if (line.empty() || line.front() == '\0') break;
        if (line.starts_with("FORMAT=")) header.formats.emplace_back(line.substr(std::strlen("FORMAT=")));
        if (line.starts_with("EXPOSURE=")) {
            const double e = headerNumbers(path, line, "EXPOSURE=", 1)[0];
            for (double& m : header.multiplier) m *= e;
        }
        if (line.starts_with("COLORCORR=")) {
            const std::vector<double> c = headerNumbers(path, line, "COLORCORR=", 3);
            for (size_t i = 0; i < 3; ++i) header.multiplier[i] *= c[i];
        }
        pos = end;
    }
    // Many lines can multiply past a double's range: dividing by 0 or infinity gives no radiance.
    for (const double m : header.multiplier)
        if (!std::isnormal(m)) {
            std::ostringstream product;
            product << m;
            throw ImageError(path, "corrupt header: its EXPOSURE= and COLORCORR= lines multiply to " + product.str() +
                                       ", past the range of a number");
        }
    return header;
}

/// The resolution line's order of the pixels. The standard one, "-Y H +X W", is scanlines top
/// to bottom, each left to right, and the only one stb_image reads; the other seven (a bottom-up
/// "+Y", a mirrored "-X", and the transposed "+X W -Y H" forms) hold the same pixels in another
/// order, so the line is read here, stb is handed the standard one, and the pixels are put back.
struct ScanOrder {
    bool transposed = false;   ///< Scanlines run along Y (the line names X first).
    bool rowsUp = false;       ///< Along Y, bottom to top ("+Y").
    bool columnsLeft = false;  ///< Along X, right to left ("-X").
    uint64_t width = 0, height = 0;  ///< As the header says: checked against the limits before use.
};

std::optional<ScanOrder> readScanOrder(const std::string& line) {
    char s1 = 0, a1 = 0, s2 = 0, a2 = 0;
    unsigned long n1 = 0, n2 = 0;
    int used = 0;
    if (std::sscanf(line.c_str(), "%c%c %lu %c%c %lu%n", &s1, &a1, &n1, &s2, &a2, &n2, &used) != 6 ||
        size_t(used) != line.size())
        return std::nullopt;
    const auto sign = [](char c) { return c == '+' || c == '-'; };
    if (!sign(s1) || !sign(s2) || !((a1 == 'Y' && a2 == 'X') || (a1 == 'X' && a2 == 'Y'))) return std::nullopt;
    ScanOrder o;
    o.transposed = a1 == 'X';
    o.rowsUp = (o.transposed ? s2 : s1) == '+';
    o.columnsLeft = (o.transposed ? s1 : s2) == '-';
    // strtoul saturates; past int64 it is past every limit all the same.
    const auto size = [](unsigned long n) { return std::min<uint64_t>(n, INT64_MAX); };
    o.width = size(o.transposed ? n1 : n2);
    o.height = size(o.transposed ? n2 : n1);
    return o;
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
    int len = static_cast<int>(bytes.size());
    if (!stbi_is_hdr_from_memory(data, len)) {
        const std::string kind = sniffFormat(bytes);
        if (kind == "a Radiance HDR image")  // the signature, but not on a line of its own
            throw ImageError(path, "corrupt header: its #?RADIANCE or #?RGBE signature must end its line with a "
                                   "newline alone (this one is followed by other bytes, e.g. CR LF line ends)");
        throw ImageError(path, "not a Radiance HDR image (" +
                                   (kind.empty() ? "no #?RADIANCE or #?RGBE signature" : "it is " + kind) + ")");
    }
    const RadianceHeader header = readHeader(path, bytes);
    // stb_image reads only FORMAT=32-bit_rle_rgbe and calls any other header unknown.
    if (const std::vector<std::string>& formats = header.formats;
        !formats.empty() && std::find(formats.begin(), formats.end(), "32-bit_rle_rgbe") == formats.end()) {
        if (std::find(formats.begin(), formats.end(), "32-bit_rle_xyze") != formats.end())
            throw ImageError(path, "XYZE .hdr files (FORMAT=32-bit_rle_xyze) are not supported; only "
                                   "FORMAT=32-bit_rle_rgbe is");
        const std::string& format = formats.front();
        const std::string shown = format.size() > 40 ? format.substr(0, 40) + "..." : format;
        throw ImageError(path, "unknown pixel format FORMAT=" + shown + "; expected FORMAT=32-bit_rle_rgbe");
    }
    // stb is handed the scanlines as the file orders them, under the standard line.
    const size_t resolutionAt = resolutionLineOffset(bytes);
    const size_t resolutionEnd = std::min(bytes.find('\n', resolutionAt), bytes.size());
    const std::optional<ScanOrder> order =
        readScanOrder(bytes.substr(resolutionAt, resolutionEnd - resolutionAt));
    // Checked as the header says it: stb keeps only the low 32 bits of each number, so a size
    // past them would load as another, smaller image.
    if (order) image_detail::requireLoadableSize(path, int64_t(order->width), int64_t(order->height));
    std::string reordered;
    if (order && (order->transposed || order->rowsUp || order->columnsLeft)) {
        const auto scanlines = static_cast<uint32_t>(order->transposed ? order->width : order->height);
        const auto perScanline = static_cast<uint32_t>(order->transposed ? order->height : order->width);
        const std::string standard = "-Y " + std::to_string(scanlines) + " +X " + std::to_string(perScanline);
        reordered = bytes.substr(0, resolutionAt) + standard + bytes.substr(resolutionEnd);
        data = reinterpret_cast<const stbi_uc*>(reordered.data());
        len = static_cast<int>(reordered.size());
    }
    const std::string& stream = reordered.empty() ? bytes : reordered;
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(data, len, &w, &h, &comp))
        throw ImageError(path, std::string("corrupt or truncated header: ") + stbi_failure_reason());
    image_detail::requireLoadableSize(path, w, h);
    if (size_t(w) * size_t(h) * 3 * sizeof(float) > size_t(INT_MAX))
        throw ImageError(path, "size " + std::to_string(w) + "x" + std::to_string(h) +
                                   " is over stb_image's 2 GiB decode limit for .hdr; use .exr");
    checkRgbeStream(path, stream, rgbeDataOffset(stream), size_t(w), size_t(h));

    std::unique_ptr<float, void (*)(void*)> rgb(stbi_loadf_from_memory(data, len, &w, &h, &comp, 3),
                                                stbi_image_free);
    if (!rgb) throw ImageError(path, std::string("cannot decode: ") + stbi_failure_reason());
    const ScanOrder o = order.value_or(ScanOrder{false, false, false, uint64_t(w), uint64_t(h)});
    HdrImage image{uint32_t(o.width), uint32_t(o.height), {}};
    image.rgba.resize(size_t(o.width) * o.height * 4);
    // Pixel j of scanline i in the file, at its place in the image (top row first, left to right).
    for (size_t i = 0; i < size_t(h); ++i)
        for (size_t j = 0; j < size_t(w); ++j) {
            size_t x = o.transposed ? i : j, y = o.transposed ? j : i;
            if (o.columnsLeft) x = o.width - 1 - x;
            if (o.rowsUp) y = o.height - 1 - y;
            float* to = &image.rgba[(y * o.width + x) * 4];
            const float* from = rgb.get() + (i * size_t(w) + j) * 3;
            // A small exposure divides out to more than a float holds: the largest float, for
            // the environment loaders to clamp as they clamp any value past half-float range.
            for (size_t c = 0; c < 3; ++c)
                to[c] = static_cast<float>(std::min(from[c] / header.multiplier[c], double(FLT_MAX)));
            to[3] = 1.0f;
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
