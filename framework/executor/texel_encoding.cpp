#include "texel_encoding.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace skygraph::detail {
namespace {

uint16_t toHalf(float f) {
    uint32_t x;
    std::memcpy(&x, &f, 4);
    const uint32_t sign = (x >> 16) & 0x8000u;
    int32_t exp = static_cast<int32_t>((x >> 23) & 0xffu) - 127 + 15;
    uint32_t mant = x & 0x7fffffu;
    if (exp <= 0) return static_cast<uint16_t>(sign);
    if (exp >= 31) return static_cast<uint16_t>(sign | 0x7c00u);
    return static_cast<uint16_t>(sign | (static_cast<uint32_t>(exp) << 10) | (mant >> 13));
}

uint8_t unorm8(float v) {
    return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

VkImageAspectFlags copyAspectOf(const FormatInfo& f) {
    if (!f.isDepthStencil()) return VK_IMAGE_ASPECT_COLOR_BIT;
    return f.hasDepth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_STENCIL_BIT;
}

uint32_t copyTexelBytes(const FormatInfo& f) {
    if (!f.isDepthStencil()) return f.bytesPerTexel;
    switch (f.format) {
        case VK_FORMAT_D16_UNORM: case VK_FORMAT_D16_UNORM_S8_UINT: return 2;
        case VK_FORMAT_S8_UINT: return 1;
        default: return 4;  // D32, D24 (packed in 4 bytes), X8_D24
    }
}

VkDeviceSize uploadBytes(const FormatInfo& format, uint32_t width, uint32_t height, uint32_t layers) {
    return VkDeviceSize(width) * height * layers * copyTexelBytes(format);
}

VkClearColorValue clearColorOf(VkFormat format, const std::array<float, 4>& color) {
    VkClearColorValue v{};
    const std::string prefix = scalarPrefix(format);
    for (size_t k = 0; k < 4; ++k) {
        // Clamped first: converting a float outside the integer's range is undefined.
        if (prefix == "u") v.uint32[k] = static_cast<uint32_t>(std::clamp(color[k], 0.0f, 4294967040.0f));
        else if (prefix == "i") v.int32[k] = static_cast<int32_t>(std::clamp(color[k], -2147483648.0f, 2147483520.0f));
        else v.float32[k] = color[k];
    }
    return v;
}

std::string scalarPrefix(VkFormat format) {
    switch (format) {
        case VK_FORMAT_R8_UINT: case VK_FORMAT_R8G8_UINT: case VK_FORMAT_R8G8B8A8_UINT:
        case VK_FORMAT_R16_UINT: case VK_FORMAT_R16G16_UINT: case VK_FORMAT_R16G16B16A16_UINT:
        case VK_FORMAT_R32_UINT: case VK_FORMAT_R32G32_UINT: case VK_FORMAT_R32G32B32A32_UINT:
        case VK_FORMAT_A2B10G10R10_UINT_PACK32:
        case VK_FORMAT_S8_UINT:  // its views see the stencil aspect alone: unsigned integers
            return "u";
        case VK_FORMAT_R8_SINT: case VK_FORMAT_R8G8_SINT: case VK_FORMAT_R8G8B8A8_SINT:
        case VK_FORMAT_R16_SINT: case VK_FORMAT_R16G16_SINT: case VK_FORMAT_R16G16B16A16_SINT:
        case VK_FORMAT_R32_SINT: case VK_FORMAT_R32G32_SINT: case VK_FORMAT_R32G32B32A32_SINT:
            return "i";
        default:
            return "";
    }
}

std::vector<uint8_t> encodeTexel(VkFormat format, uint32_t texelBytes, const std::array<float, 4>& c) {
    std::vector<uint8_t> out(texelBytes, 0);
    auto put = [&](const void* p, size_t n) {
        std::memcpy(out.data(), p, std::min<size_t>(n, out.size()));
    };
    switch (format) {
        case VK_FORMAT_R8G8B8A8_UNORM:
        case VK_FORMAT_R8G8B8A8_SRGB: {
            const uint8_t b[4] = {unorm8(c[0]), unorm8(c[1]), unorm8(c[2]), unorm8(c[3])};
            put(b, 4);
            break;
        }
        case VK_FORMAT_B8G8R8A8_UNORM:
        case VK_FORMAT_B8G8R8A8_SRGB: {
            const uint8_t b[4] = {unorm8(c[2]), unorm8(c[1]), unorm8(c[0]), unorm8(c[3])};
            put(b, 4);
            break;
        }
        case VK_FORMAT_R8_UNORM: {
            const uint8_t b = unorm8(c[0]);
            put(&b, 1);
            break;
        }
        case VK_FORMAT_R16G16B16A16_SFLOAT:
        case VK_FORMAT_R16G16_SFLOAT:
        case VK_FORMAT_R16_SFLOAT: {
            const uint16_t h[4] = {toHalf(c[0]), toHalf(c[1]), toHalf(c[2]), toHalf(c[3])};
            put(h, 8);
            break;
        }
        case VK_FORMAT_R32G32B32A32_SFLOAT:
        case VK_FORMAT_R32G32_SFLOAT:
        case VK_FORMAT_R32_SFLOAT:
            put(c.data(), 16);
            break;
        case VK_FORMAT_D32_SFLOAT:
        case VK_FORMAT_D32_SFLOAT_S8_UINT: {
            const float d = std::clamp(c[0], 0.0f, 1.0f);
            put(&d, 4);
            break;
        }
        case VK_FORMAT_D16_UNORM: {
            const auto d = static_cast<uint16_t>(std::lround(std::clamp(c[0], 0.0f, 1.0f) * 65535.0f));
            put(&d, 2);
            break;
        }
        default:
            break;
    }
    return out;
}

void fillBufferPattern(uint8_t* dst, uint64_t bytes, float value) {
    const size_t words = static_cast<size_t>(bytes / 4);
    uint32_t valueBits;
    std::memcpy(&valueBits, &value, 4);
    for (size_t i = 0; i < words; ++i) {
        const uint32_t w = i == 0 ? 3u : i == 1 ? 1u : i < 8 ? 0u : valueBits;
        std::memcpy(dst + i * 4, &w, 4);
    }
}

}  // namespace skygraph::detail
