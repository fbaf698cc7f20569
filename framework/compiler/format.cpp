#include <skygraph/format.hpp>

#include "format_table.hpp"

namespace skygraph {

std::optional<FormatInfo> findFormat(std::string_view name) noexcept {
    for (const auto& f : format_table::kFormats)
        if (f.name == name) return f;
    return std::nullopt;
}

std::optional<FormatInfo> findFormat(VkFormat format) noexcept {
    if (const FormatInfo* known = format_table::entryOf(format)) return *known;
    return std::nullopt;
}

std::string formatName(VkFormat format) {
    const auto info = findFormat(format);
    return info ? std::string(info->name) : "VkFormat " + std::to_string(int(format));
}

std::span<const FormatInfo> knownFormats() noexcept { return format_table::kFormats; }

}  // namespace skygraph
