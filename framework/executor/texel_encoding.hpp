// Contents the executor writes itself, laid out as the device reads them: texels of a format
// (uploads, the first contents of externals), the buffer pattern, and the layout of copies
// between buffers and images. Pass implementations that copy or fill resources use the same
// rules, so that what they write matches what the executor writes.
#pragma once

#include <skygraph/format.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace skygraph::detail {

/// Aspect for buffer<->image copies: one aspect only (depth for depth formats).
[[nodiscard]] VkImageAspectFlags copyAspectOf(const FormatInfo& format);

/// Bytes of one texel in a buffer<->image copy of `format` (its copied aspect only).
[[nodiscard]] uint32_t copyTexelBytes(const FormatInfo& format);

/// Bytes of a tightly packed copy of mip 0 of `layers` layers of a width x height image of
/// `format`: what Renderer::stageUpload() takes and UploadPass copies.
[[nodiscard]] VkDeviceSize uploadBytes(const FormatInfo& format, uint32_t width, uint32_t height, uint32_t layers);

/// Whether a format stores unsigned ("u") or signed ("i") integers, else "": the GLSL prefix
/// of its sampler, image and output types.
[[nodiscard]] std::string scalarPrefix(VkFormat format);

/// `color` as a clear of `format` reads it: floats, or for integer formats the integers they
/// hold (the loader allows integers only there), clamped to 32 bits.
[[nodiscard]] VkClearColorValue clearColorOf(VkFormat format, const std::array<float, 4>& color);

/// Bytes of one texel of `format` filled with `color` (depth formats take color.x). Unknown
/// encodings yield zero bytes.
[[nodiscard]] std::vector<uint8_t> encodeTexel(VkFormat format, uint32_t texelBytes, const std::array<float, 4>& color);

/// The buffer pattern: {3, 1, 0, 0, 0, 0, 0, 0, floatBits(value), ...} in 32-bit words, a valid
/// draw-indirect and indexed-indirect command and the index list {3, 1, 0}, with `value` from
/// element 8 on: what a buffer holds before anything writes it (docs/executor.md).
void fillBufferPattern(uint8_t* dst, uint64_t bytes, float value);

}  // namespace skygraph::detail
