// The formats skygraph knows, as one table: what findFormat() answers from, and what the
// compiler checks each image's FormatInfo against (graph_limits.hpp), inline, as it asks once
// per resource.
#pragma once

#include <skygraph/format.hpp>

#include <array>
#include <cstddef>
#include <cstdint>

namespace skygraph {
namespace format_table {

// storageCapable follows the spec's table of formats with mandatory STORAGE_IMAGE support,
// plus the widely available ones (B8G8R8A8_UNORM: the storage swapchain format that surfaces
// offer); sRGB and depth formats are never storage images. The executor asks the device.
#define SG_FORMAT(name, bytes, depth, stencil, srgb, storage) \
    FormatInfo{#name, VK_FORMAT_##name, bytes, depth, stencil, srgb, storage}

inline constexpr std::array kFormats{
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

// Every format above is a core one, numbered below 256: its entry + 1, by VkFormat, so that
// the check of each resource's format in compile() is one load.
inline constexpr size_t kCoreFormats = 256;
inline constexpr auto kEntryOf = [] {
    std::array<uint8_t, kCoreFormats> entry{};
    for (size_t i = 0; i < kFormats.size(); ++i) entry[static_cast<size_t>(kFormats[i].format)] = uint8_t(i + 1);
    return entry;
}();
static_assert(kFormats.size() < 256);

[[nodiscard]] inline const FormatInfo* entryOf(VkFormat format) noexcept {
    const auto v = static_cast<size_t>(format);
    return v < kCoreFormats && kEntryOf[v] != 0 ? &kFormats[kEntryOf[v] - 1] : nullptr;
}

/// What a colour clear of a format holds as written (docs/graph-format.md, `clear`). The spec
/// converts a clear value to the format: a normalized or shared-exponent format clamps it into
/// its range, a float format's overflow is the implementation's, and a channel the format
/// lacks is ignored. A value outside is refused, not changed.
struct ClearColorRange {
    double lowest = 0, highest = 0;  ///< Every channel holds both; empty for depth/stencil formats.
    bool integers = false;           ///< UINT and SINT: the clear writes integers, kept as floats.

    /// A format skygraph does not know, or a depth/stencil one: no colour clear to hold.
    [[nodiscard]] constexpr bool empty() const noexcept { return highest == 0; }
    /// Whether a channel's value `v` fits, `whole` saying whether it is written as an integer.
    [[nodiscard]] constexpr bool holds(double v, bool whole) const noexcept {
        return v >= lowest && v <= highest && (whole || !integers);
    }
};

[[nodiscard]] constexpr ClearColorRange clearColorRange(VkFormat format) noexcept {
    constexpr double kExactInFloat = 16777216.0;  // 2^24: a float holds every integer up to it
    constexpr double kHalfMax = 65504.0;
    // The largest double that a graph file's number, stored as a float, rounds to FLT_MAX from
    // rather than to infinity: FLT_MAX plus half its ulp, less a double's ulp there.
    constexpr double kFloatMax = 3.40282346638528859812e+38 + 0x1p103 - 0x1p76;
    switch (format) {
        case VK_FORMAT_R8_UNORM: case VK_FORMAT_R8G8_UNORM: case VK_FORMAT_R8G8B8A8_UNORM:
        case VK_FORMAT_R8G8B8A8_SRGB: case VK_FORMAT_B8G8R8A8_UNORM: case VK_FORMAT_B8G8R8A8_SRGB:
        case VK_FORMAT_A2B10G10R10_UNORM_PACK32: case VK_FORMAT_R16G16B16A16_UNORM: return {0.0, 1.0};
        case VK_FORMAT_R8G8B8A8_SNORM: return {-1.0, 1.0};
        case VK_FORMAT_B10G11R11_UFLOAT_PACK32: return {0.0, 64512.0};  // blue's 10 bits: the least of the three
        case VK_FORMAT_E5B9G9R9_UFLOAT_PACK32: return {0.0, 65408.0};
        case VK_FORMAT_R16_SFLOAT: case VK_FORMAT_R16G16_SFLOAT: case VK_FORMAT_R16G16B16A16_SFLOAT:
            return {-kHalfMax, kHalfMax};
        case VK_FORMAT_R32_SFLOAT: case VK_FORMAT_R32G32_SFLOAT: case VK_FORMAT_R32G32B32A32_SFLOAT:
            return {-kFloatMax, kFloatMax};
        case VK_FORMAT_R32_UINT: case VK_FORMAT_R32G32B32A32_UINT: return {0.0, kExactInFloat, true};
        case VK_FORMAT_R32_SINT: return {-kExactInFloat, kExactInFloat, true};
        default: return {};
    }
}

static_assert([] {
    for (const FormatInfo& f : kFormats)
        if ((f.hasDepth || f.hasStencil) != clearColorRange(f.format).empty()) return false;
    return true;
}(), "every colour format of the table has a clear range, and no depth/stencil format has one");

}  // namespace format_table

/// Whether `f` is the table's entry for f.format, field by field.
[[nodiscard]] inline bool formatInfoMatches(const FormatInfo& f) noexcept {
    const FormatInfo* known = format_table::entryOf(f.format);
    // Nearly every FormatInfo is a copy of the table's own, whose name views the table's text.
    return known && f.bytesPerTexel == known->bytesPerTexel && f.hasDepth == known->hasDepth &&
           f.hasStencil == known->hasStencil && f.srgb == known->srgb && f.storageCapable == known->storageCapable &&
           ((f.name.data() == known->name.data() && f.name.size() == known->name.size()) || f.name == known->name);
}

}  // namespace skygraph
