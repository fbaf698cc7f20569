// encodeKtx2: the KTX 2.0 layout (spec §3): identifier, header, index, level index, data format
// descriptor (one basic block, KHR_DF_MODEL_RGBSDA, linear), key/value data, then the levels,
// smallest first, each aligned to lcm(texel size, 4).
#include <skygraph/ktx2.hpp>

#include "image_internal.hpp"

#include <Imath/half.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <string>

namespace skygraph {
namespace {

struct FormatFacts {
    uint32_t channels;     // 2 (RG) or 4 (RGBA)
    uint32_t channelBytes; // 2 (half) or 4 (float)
};

FormatFacts factsOf(Ktx2Format f) {
    switch (f) {
        case Ktx2Format::Rgba16Float: return {4, 2};
        case Ktx2Format::Rgba32Float: return {4, 4};
        case Ktx2Format::Rg16Float: return {2, 2};
        case Ktx2Format::Rg32Float: return {2, 4};
    }
    return {4, 2};
}

class ByteWriter {
public:
    void u32(uint32_t v) { raw(&v, 4); }
    void u64(uint64_t v) { raw(&v, 8); }
    void raw(const void* p, size_t n) { bytes.append(static_cast<const char*>(p), n); }
    void padTo(size_t alignment) {
        while (bytes.size() % alignment) bytes.push_back('\0');
    }
    void putU32At(size_t offset, uint32_t v) { std::memcpy(bytes.data() + offset, &v, 4); }
    void putU64At(size_t offset, uint64_t v) { std::memcpy(bytes.data() + offset, &v, 8); }
    std::string bytes;  // little-endian host assumed (x86-64, arm64)
};

/// The basic data format descriptor block of an uncompressed float RGBA/RG format.
void writeDataFormatDescriptor(ByteWriter& w, const FormatFacts& f) {
    const uint32_t blockSize = 24 + 16 * f.channels;
    w.u32(4 + blockSize);                          // dfdTotalSize
    w.u32(0);                                      // vendorId 0 (Khronos), descriptorType 0 (basic)
    w.u32(2u | (blockSize << 16));                 // versionNumber 2 (KDFS 1.3), descriptorBlockSize
    w.u32(1u | (1u << 8) | (1u << 16) | (0u << 24));  // RGBSDA, BT.709 primaries, linear, straight alpha
    w.u32(0);                                      // texel block 1x1x1x1
    w.u32(f.channels * f.channelBytes);            // bytesPlane0
    w.u32(0);                                      // bytesPlane4..7
    const uint32_t ids[4] = {0, 1, 2, 15};         // R, G, B, A
    for (uint32_t c = 0; c < f.channels; ++c) {
        const uint32_t bits = f.channelBytes * 8;
        const uint32_t channelType = ids[c] | 0x80u /* float */ | 0x40u /* signed */;
        w.u32((c * bits) | ((bits - 1) << 16) | (channelType << 24));
        w.u32(0);                                  // sample position
        w.u32(0xBF800000u);                        // sampleLower: -1.0f (float formats)
        w.u32(0x3F800000u);                        // sampleUpper: 1.0f
    }
}

void writeKeyValue(ByteWriter& w, const std::string& key, const std::string& value) {
    const uint32_t length = uint32_t(key.size() + 1 + value.size() + 1);
    w.u32(length);
    w.raw(key.c_str(), key.size() + 1);
    w.raw(value.c_str(), value.size() + 1);
    w.padTo(4);
}

void appendTexels(ByteWriter& w, const HdrImage& image, const FormatFacts& f) {
    for (size_t p = 0; p < size_t(image.width) * image.height; ++p)
        for (uint32_t c = 0; c < f.channels; ++c) {
            const float v = image.rgba[p * 4 + c];
            if (f.channelBytes == 4) {
                w.raw(&v, 4);
            } else {
                const uint16_t h = Imath::half(v).bits();
                w.raw(&h, 2);
            }
        }
}

void checkTexture(const std::filesystem::path& path, const Ktx2Texture& t) {
    if (t.levels.empty() || t.levels[0].empty()) throw ImageError(path, "KTX2: no levels to write");
    const size_t faces = t.levels[0].size();
    if (faces != 1 && faces != 6) throw ImageError(path, "KTX2: a texture has 1 face or 6 (a cube)");
    const uint32_t width = t.levels[0][0].width, height = t.levels[0][0].height;
    if (faces == 6 && width != height) throw ImageError(path, "KTX2: cube faces must be square");
    for (size_t m = 0; m < t.levels.size(); ++m) {
        if (t.levels[m].size() != faces)
            throw ImageError(path, "KTX2: level " + std::to_string(m) + " has " + std::to_string(t.levels[m].size()) +
                                       " faces, level 0 has " + std::to_string(faces));
        for (const HdrImage& img : t.levels[m]) {
            const uint32_t w = std::max(1u, width >> m), h = std::max(1u, height >> m);
            if (img.width != w || img.height != h || img.rgba.size() != size_t(w) * h * 4)
                throw ImageError(path, "KTX2: level " + std::to_string(m) + " must be " + std::to_string(w) + "x" +
                                           std::to_string(h));
        }
    }
}

}  // namespace

std::string encodeKtx2(const std::filesystem::path& path, const Ktx2Texture& texture) {
    checkTexture(path, texture);
    const FormatFacts facts = factsOf(texture.format);
    const auto levelCount = uint32_t(texture.levels.size());
    const auto faceCount = uint32_t(texture.levels[0].size());
    const HdrImage& base = texture.levels[0][0];

    ByteWriter w;
    const uint8_t identifier[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
    w.raw(identifier, 12);
    w.u32(uint32_t(texture.format));
    w.u32(facts.channelBytes);  // typeSize
    w.u32(base.width);
    w.u32(base.height);
    w.u32(0);           // pixelDepth: not 3D
    w.u32(0);           // layerCount: not an array
    w.u32(faceCount);
    w.u32(levelCount);
    w.u32(0);           // no supercompression
    const size_t indexAt = w.bytes.size();
    for (int i = 0; i < 4; ++i) w.u32(0);  // dfd offset/length, kvd offset/length: patched below
    w.u64(0);
    w.u64(0);  // no supercompression global data
    const size_t levelIndexAt = w.bytes.size();
    for (uint32_t m = 0; m < levelCount * 3; ++m) w.u64(0);  // patched below

    const size_t dfdAt = w.bytes.size();
    writeDataFormatDescriptor(w, facts);
    const size_t kvdAt = w.bytes.size();
    writeKeyValue(w, "KTXorientation", "rd");
    writeKeyValue(w, "KTXwriter", "skygraph cubemap");
    const size_t kvdEnd = w.bytes.size();
    w.putU32At(indexAt, uint32_t(dfdAt));
    w.putU32At(indexAt + 4, uint32_t(kvdAt - dfdAt));
    w.putU32At(indexAt + 8, uint32_t(kvdAt));
    w.putU32At(indexAt + 12, uint32_t(kvdEnd - kvdAt));

    const size_t alignment = std::lcm(size_t(facts.channels * facts.channelBytes), size_t(4));
    for (uint32_t m = levelCount; m-- > 0;) {  // smallest level first (spec §3.9)
        w.padTo(alignment);
        const size_t start = w.bytes.size();
        for (const HdrImage& face : texture.levels[m]) appendTexels(w, face, facts);
        const size_t length = w.bytes.size() - start;
        w.putU64At(levelIndexAt + m * 24, start);
        w.putU64At(levelIndexAt + m * 24 + 8, length);
        w.putU64At(levelIndexAt + m * 24 + 16, length);
    }

    return std::move(w.bytes);
}

void saveKtx2(const std::filesystem::path& path, const Ktx2Texture& texture) {
    image_detail::writeBytes(path, encodeKtx2(path, texture));
}

}  // namespace skygraph
