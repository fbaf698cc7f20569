// The image formats skygraph understands, by their graph-file names.
#pragma once

#include <vulkan/vulkan_core.h>

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace skygraph {

/// Static facts about a VkFormat that the compiler needs to check usages without a device.
/// Take it from findFormat(): compile() refuses an image whose FormatInfo differs from that in
/// any field, or whose format is not one of knownFormats().
struct FormatInfo {
    /// Graph-file spelling: the VkFormat name without "VK_FORMAT_". Static storage in every
    /// FormatInfo that findFormat() and knownFormats() give.
    std::string_view name;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t bytesPerTexel = 0;
    bool hasDepth = false;
    bool hasStencil = false;
    bool srgb = false;
    /// Whether storage-image use is plausible (the compiler refuses `as: storage` otherwise); the
    /// executor still asks the device.
    bool storageCapable = false;

    [[nodiscard]] bool isDepthStencil() const noexcept { return hasDepth || hasStencil; }
};

/// nullopt for names skygraph does not know; `knownFormats()` lists the ones it does.
/// Returns a copy; `name` is read during the call only.
[[nodiscard]] std::optional<FormatInfo> findFormat(std::string_view name) noexcept;
[[nodiscard]] std::optional<FormatInfo> findFormat(VkFormat format) noexcept;
/// For messages: "R16G16B16A16_SFLOAT" as graph files name it, or "VkFormat 1000" for a
/// format skygraph does not know.
[[nodiscard]] std::string formatName(VkFormat format);
/// A view of a static table: valid for the whole program.
[[nodiscard]] std::span<const FormatInfo> knownFormats() noexcept;

}  // namespace skygraph
