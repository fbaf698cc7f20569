#include <skygraph/format.hpp>

#include <array>

namespace skygraph {
namespace {

// storageCapable follows the spec's table of formats with mandatory STORAGE_IMAGE support,
// plus the widely available ones (B8G8R8A8_UNORM: the storage swapchain format that surfaces
// offer); sRGB and depth formats are never storage images. The executor asks the device.
#define SG_FORMAT(name, bytes, depth, stencil, srgb, storage) \
    FormatInfo{#name, VK_FORMAT_##name, bytes, depth, stencil, srgb, storage}

constexpr std::array kFormats{
    SG_FORMAT(R8_UNORM, 1, false, false, false, true),
    SG_FORMAT(R8G8_UNORM, 2, false, false, false, true),
    SG_FORMAT(R8G8B8A8_UNORM, 4, false, false, false, true),
    SG_FORMAT(R8G8B8A8_SNORM, 4, false, false, false, true),
    SG_FORMAT(R8G8B8A8_SRGB, 4, false, false, true, false),
    SG_FORMAT(B8G8R8A8_UNORM, 4, false, false, false, true),
    SG_FORMAT(B8G8R8A8_SRGB, 4, false, false, true, false),
    SG_FORMAT(A2B10G10R10_UNORM_PACK32, 4, false, false, false, false),
    SG_FORMAT(B10G11R11_UFLOAT_PACK32, 4, false, false, false, false),
    SG_FORMAT(E5B9G9R9_UFLOAT_PACK32, 4, false, false, false, false),
    SG_FORMAT(R16_SFLOAT, 2, false, false, false, true),
    SG_FORMAT(R16G16_SFLOAT, 4, false, false, false, true),
    SG_FORMAT(R16G16B16A16_SFLOAT, 8, false, false, false, true),
    SG_FORMAT(R16G16B16A16_UNORM, 8, false, false, false, true),
    SG_FORMAT(R32_SFLOAT, 4, false, false, false, true),
    SG_FORMAT(R32_UINT, 4, false, false, false, true),
    SG_FORMAT(R32_SINT, 4, false, false, false, true),
    SG_FORMAT(R32G32_SFLOAT, 8, false, false, false, true),
    SG_FORMAT(R32G32B32A32_SFLOAT, 16, false, false, false, true),
    SG_FORMAT(R32G32B32A32_UINT, 16, false, false, false, true),
    SG_FORMAT(D16_UNORM, 2, true, false, false, false),
    SG_FORMAT(D32_SFLOAT, 4, true, false, false, false),
    SG_FORMAT(X8_D24_UNORM_PACK32, 4, true, false, false, false),
    SG_FORMAT(D24_UNORM_S8_UINT, 4, true, true, false, false),
    SG_FORMAT(D32_SFLOAT_S8_UINT, 8, true, true, false, false),
    SG_FORMAT(S8_UINT, 1, false, true, false, false),
};
#undef SG_FORMAT

}  // namespace

std::optional<FormatInfo> findFormat(std::string_view name) noexcept {
    for (const auto& f : kFormats)
        if (f.name == name) return f;
    return std::nullopt;
}

std::optional<FormatInfo> findFormat(VkFormat format) noexcept {
    for (const auto& f : kFormats)
        if (f.format == format) return f;
    return std::nullopt;
}

std::string formatName(VkFormat format) {
    const auto info = findFormat(format);
    return info ? std::string(info->name) : "VkFormat " + std::to_string(int(format));
}

std::span<const FormatInfo> knownFormats() noexcept { return kFormats; }

}  // namespace skygraph
