// OpenEXR (.exr): any compression OpenEXR knows (ZIP, PIZ, DWAA, DWAB, ...), read at float
// precision through Imf::InputFile; chroma-subsampled luminance files through Imf::RgbaInputFile.
#include "image_internal.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfThreading.h>
#include <OpenEXR/ImfTestFile.h>
#include <OpenEXR/ImfVersion.h>
#include <OpenEXR/ImfXdr.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>

namespace skygraph {
namespace {

/// OpenEXR's output stream into memory. RgbaOutputFile seeks back to write its offset table
/// when it is done, so the bytes are written at the stream's position, not appended.
class MemoryStream : public Imf::OStream {
public:
    /// `path`: the file the bytes are for, which OpenEXR's messages name.
    explicit MemoryStream(const std::filesystem::path& path) : Imf::OStream(path.c_str()) {}
    void write(const char c[], int n) override {
        const size_t end = position_ + size_t(n);
        if (end > bytes.size()) bytes.resize(end);
        std::copy(c, c + n, bytes.begin() + std::ptrdiff_t(position_));
        position_ = end;
    }
    uint64_t tellp() override { return position_; }
    void seekp(uint64_t position) override { position_ = size_t(position); }
    std::string bytes;

private:
    size_t position_ = 0;
};

/// The first header, read alone (the magic number, the version field, the attributes) so that
/// the file is known to be an OpenEXR file before anything else is believed of it, and so that
/// its size can be refused before OpenEXR or we allocate anything in proportion to it. Throws
/// ImageError for a version field OpenEXR does not write or a header it cannot read.
Imf::Header readFirstHeader(const std::filesystem::path& path) {
    const auto invalid = [&](const std::string& why) { return ImageError(path, "not a valid OpenEXR file: " + why); };
    try {
        Imf::StdIFStream stream(path.c_str());
        int magic = 0, version = 0;
        Imf::Xdr::read<Imf::StreamIO>(stream, magic);
        Imf::Xdr::read<Imf::StreamIO>(stream, version);
        if (Imf::getVersion(version) != Imf::EXR_VERSION || !Imf::supportsFlags(Imf::getFlags(version))) {
            char field[16];
            std::snprintf(field, sizeof field, "0x%08x", unsigned(version));
            throw invalid(std::string("unknown version field ") + field + "; OpenEXR files are version 2");
        }
        Imf::Header header;
        header.readFrom(stream, version);
        return header;
    } catch (const ImageError&) {
        throw;
    } catch (const std::exception& e) {  // Iex::BaseExc and std::bad_alloc
        throw invalid(std::string("truncated or corrupt header (") + e.what() + ")");
    }
}

/// OpenEXR decompresses a file's blocks on its global thread pool, which is empty until it is
/// given threads: one per core, once. A 6K ZIP frame reads several times faster.
int decodeThreads() {
    static const int threads = [] {
        const int n = int(std::max(1u, std::thread::hardware_concurrency()));
        Imf::setGlobalThreadCount(n);
        return n;
    }();
    return threads;
}

void readPixels(const std::filesystem::path& path, Imf::InputFile& file, const Imath::Box2i& window, HdrImage& image) {
    const Imf::ChannelList& channels = file.header().channels();
    const bool rgb = channels.findChannel("R") || channels.findChannel("G") || channels.findChannel("B");
    if (!rgb && (channels.findChannel("RY") || channels.findChannel("BY"))) {
        Imf::RgbaInputFile yc(path.c_str(), decodeThreads());  // converts luminance/chroma to RGB (half precision)
        std::vector<Imf::Rgba> half(size_t(image.width) * image.height);
        yc.setFrameBuffer(half.data() - window.min.x - ptrdiff_t(window.min.y) * image.width, 1,
                          image.width);
        yc.readPixels(window.min.y, window.max.y);
        for (size_t i = 0; i < half.size(); ++i) {
            const Imf::Rgba& p = half[i];
            float* out = image.rgba.data() + i * 4;
            out[0] = p.r, out[1] = p.g, out[2] = p.b, out[3] = p.a;
        }
        return;
    }
    if (!rgb && !channels.findChannel("Y"))
        throw ImageError(path, "no R, G, B or Y channel; nothing to read as colour");
    Imf::FrameBuffer frame;
    const size_t xStride = 4 * sizeof(float), yStride = xStride * image.width;
    auto slice = [&](int c, double fill) {
        return Imf::Slice::Make(Imf::FLOAT, image.rgba.data() + c, window, xStride, yStride, 1, 1, fill);
    };
    if (rgb) {
        frame.insert("R", slice(0, 0.0));
        frame.insert("G", slice(1, 0.0));
        frame.insert("B", slice(2, 0.0));
    } else {
        frame.insert("Y", slice(0, 0.0));  // luminance only: copied to G and B below
    }
    frame.insert("A", slice(3, 1.0));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    if (!rgb)
        for (size_t i = 0; i < image.rgba.size(); i += 4) image.rgba[i + 1] = image.rgba[i + 2] = image.rgba[i];
}

}  // namespace

HdrImage loadExr(const std::filesystem::path& path) {
    image_detail::requireReadableFile(path);
    if (!Imf::isOpenExrFile(path.c_str())) {
        std::ifstream in(path, std::ios::binary);
        std::string head(16, '\0');
        in.read(head.data(), std::streamsize(head.size()));
        head.resize(size_t(in.gcount()));
        const std::string kind = image_detail::sniffFormat(head);
        if (kind == "an OpenEXR image") throw ImageError(path, "not a valid OpenEXR file: truncated or corrupt header");
        throw ImageError(path, head.empty() ? "empty file; expected an OpenEXR image"
                                            : "not an OpenEXR image (" +
                                                  (kind.empty() ? "no EXR signature" : "it is " + kind) + ")");
    }
    // Deep data is told by the header's part type, not by the version field's flag: any bytes
    // after the magic number set that flag half the time.
    const Imf::Header header = readFirstHeader(path);
    if (header.hasType() && Imf::isDeepData(header.type()))
        throw ImageError(path, "deep OpenEXR images are not supported");
    try {
        const Imath::Box2i window = header.dataWindow();
        const int64_t w = int64_t(window.max.x) - window.min.x + 1;
        const int64_t h = int64_t(window.max.y) - window.min.y + 1;
        image_detail::requireLoadableSize(path, w, h);
        // Both windows before any pixels are allocated: a few hundred bytes may claim
        // gigabytes of them.
        const Imath::Box2i display = header.displayWindow();
        const int64_t dw = int64_t(display.max.x) - display.min.x + 1;
        const int64_t dh = int64_t(display.max.y) - display.min.y + 1;
        image_detail::requireLoadableSize(path, dw, dh);
        Imf::InputFile file(path.c_str(), decodeThreads());
        if (!file.isComplete()) throw ImageError(path, "truncated: some pixel blocks are missing");
        HdrImage image{uint32_t(w), uint32_t(h), std::vector<float>(size_t(w) * size_t(h) * 4)};
        readPixels(path, file, window, image);
        // The image is the display window: pixels it holds outside the data window are
        // transparent black, and data outside it (overscan) is not part of the image.
        if (display == window) return image;
        HdrImage shown{uint32_t(dw), uint32_t(dh), std::vector<float>(size_t(dw) * size_t(dh) * 4, 0.0f)};
        for (int64_t y = 0; y < dh; ++y) {
            const int64_t sy = y + display.min.y - window.min.y;
            if (sy < 0 || sy >= h) continue;
            for (int64_t x = 0; x < dw; ++x) {
                const int64_t sx = x + display.min.x - window.min.x;
                if (sx < 0 || sx >= w) continue;
                std::copy_n(&image.rgba[size_t(sy * w + sx) * 4], 4, &shown.rgba[size_t(y * dw + x) * 4]);
            }
        }
        return shown;
    } catch (const ImageError&) {
        throw;
    } catch (const std::exception& e) {  // Iex::BaseExc and std::bad_alloc
        throw ImageError(path, std::string("corrupt or truncated OpenEXR data: ") + e.what());
    }
}

namespace image_detail {

std::string encodeExr(const std::filesystem::path& path, const HdrImage& image) {
    requireWritable(path, image);
    // Every caller's pixels go to half floats here, which round a finite value past +-65504 to
    // infinity: a bright texel of an rgba32f bake's --cross, say, would be written as +Inf. Such
    // values are clamped to the largest half instead; infinities and NaNs stay what they are.
    const auto toHalf = [](float v) {
        constexpr float kLargestHalf = float(HALF_MAX);
        return std::isfinite(v) ? std::clamp(v, -kLargestHalf, kLargestHalf) : v;
    };
    std::vector<Imf::Rgba> half(size_t(image.width) * image.height);
    for (size_t i = 0; i < half.size(); ++i) {
        const float* p = image.rgba.data() + i * 4;
        half[i] = Imf::Rgba(toHalf(p[0]), toHalf(p[1]), toHalf(p[2]), toHalf(p[3]));
    }
    MemoryStream stream(path);
    try {
        const Imf::Header header(int(image.width), int(image.height), 1.0f, Imath::V2f(0, 0), 1.0f, Imf::INCREASING_Y,
                                 Imf::ZIP_COMPRESSION);
        Imf::RgbaOutputFile out(stream, header, Imf::WRITE_RGBA);
        out.setFrameBuffer(half.data(), 1, image.width);
        out.writePixels(int(image.height));
    } catch (const std::exception& e) {  // Iex::BaseExc and std::bad_alloc
        throw ImageError(path, std::string("cannot encode: ") + e.what());
    }
    return std::move(stream.bytes);
}

}  // namespace image_detail

void saveExr(const std::filesystem::path& path, const HdrImage& image) {
    image_detail::writeBytes(path, image_detail::encodeExr(path, image));
}

}  // namespace skygraph
