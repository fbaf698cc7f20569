// What a Clobber step (CompileOptions::clobberTransients) fills a transient resource with before
// the first use that discards it: values no pass computes by accident, so that a pass reading
// what that use did not write changes the frame, and a render with clobbering differs from one
// without.
#pragma once

#include <skygraph/format.hpp>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <limits>
#include <string_view>

namespace skygraph::detail {

/// Buffers: every word 0x7FC00000, a float quiet NaN, since most buffers a pass reads hold
/// floats; as an integer (an index, a draw count) it is far out of range. vkCmdFillBuffer
/// fills whole words: the last 1-3 bytes of a buffer whose size is no multiple of 4 keep what
/// was there.
inline constexpr uint32_t kPoisonBufferWord = 0x7FC00000u;

/// The poison for an image of `format`, for vkCmdClearColorImage or (depth/stencil formats)
/// vkCmdClearDepthStencilImage:
/// - depth/stencil: depth 0.5 (a depth clear must lie in [0, 1], where no NaN is allowed; the
///   middle is neither the near nor the far plane that depth clears use) and stencil 0x5A
///   (alternating bits, not the 0 or 0xFF of a cleared stencil);
/// - float formats (SFLOAT, UFLOAT): a quiet NaN, which spreads through whatever arithmetic
///   reads it, and which blending, filtering and tonemapping keep visible;
/// - UINT/SINT: 0xDEADBEEF: recognisable, and no count or index. Every integer colour format
///   the graph format has is 32 bits a component (R32_UINT, R32G32B32A32_UINT, R32_SINT), so it
///   is written whole; a narrower SINT format would need a value it can represent (the spec
///   leaves the clear undefined otherwise).
/// - UNORM/SNORM/SRGB (no NaN to hold): magenta (1, 0, 1, 1), which no lit frame has much of.
[[nodiscard]] inline VkClearValue poisonFor(const FormatInfo& format) noexcept {
    VkClearValue v{};
    const std::string_view name = format.name;
    if (format.isDepthStencil()) {
        v.depthStencil = {0.5f, 0x5Au};
    } else if (name.find("FLOAT") != std::string_view::npos) {
        for (float& c : v.color.float32) c = std::numeric_limits<float>::quiet_NaN();
    } else if (name.find("UINT") != std::string_view::npos || name.find("SINT") != std::string_view::npos) {
        for (uint32_t& c : v.color.uint32) c = 0xDEADBEEFu;
    } else {
        v.color.float32[0] = 1.0f;
        v.color.float32[1] = 0.0f;
        v.color.float32[2] = 1.0f;
        v.color.float32[3] = 1.0f;
    }
    return v;
}

}  // namespace skygraph::detail
