// How a pass touches a resource: the vocabulary of graph files (docs/graph-format.md, "Usages").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace skygraph {

/// What a pass does with the contents of a resource.
enum class Access : uint8_t {
    Read,       ///< Reads contents written earlier.
    Write,      ///< Overwrites; whatever was there before the pass is discarded.
    ReadWrite,  ///< Reads earlier contents and modifies them (blending, accumulation).
};

/// Where in the pipeline the access happens.
enum class Stage : uint8_t {
    ColorAttachment,
    DepthAttachment,
    Vertex,
    Fragment,
    Compute,
    Transfer,
    VertexInput,
    Indirect,
};

/// How a shader stage binds the resource; meaningless for the other stages.
/// `Index` is a skygraph extension for `VertexInput` (index buffers).
enum class BindAs : uint8_t { Default, Sampled, Storage, Uniform, Index };

/// A rectangle of mip levels x array layers. Counts are never zero once resolved.
struct SubresourceRange {
    uint32_t baseMip = 0;
    uint32_t mipCount = 1;
    uint32_t baseLayer = 0;
    uint32_t layerCount = 1;

    [[nodiscard]] bool overlaps(const SubresourceRange& o) const noexcept {
        return baseMip < o.baseMip + o.mipCount && o.baseMip < baseMip + mipCount &&
               baseLayer < o.baseLayer + o.layerCount && o.baseLayer < baseLayer + layerCount;
    }
    friend bool operator==(const SubresourceRange&, const SubresourceRange&) = default;
};

/// How a usage touches its resource, without which part: what a plan keeps of a usage
/// beside the range it resolved (PlannedUsage::usage).
struct UsageMode {
    Access access = Access::Read;
    Stage stage = Stage::Fragment;
    BindAs as = BindAs::Default;

    friend bool operator==(const UsageMode&, const UsageMode&) = default;
};

/// One `uses` entry after parsing, before it is bound to a pass slot.
struct Usage {
    Access access = Access::Read;
    Stage stage = Stage::Fragment;
    BindAs as = BindAs::Default;
    /// Empty means "the whole resource"; resolved by the compiler.
    std::optional<SubresourceRange> range;

    [[nodiscard]] constexpr UsageMode mode() const noexcept { return {access, stage, as}; }
};

[[nodiscard]] constexpr bool isShaderStage(Stage s) noexcept {
    return s == Stage::Vertex || s == Stage::Fragment || s == Stage::Compute;
}
[[nodiscard]] constexpr bool isAttachmentStage(Stage s) noexcept {
    return s == Stage::ColorAttachment || s == Stage::DepthAttachment;
}
[[nodiscard]] constexpr bool readsContents(Access a) noexcept { return a != Access::Write; }  ///< Read or ReadWrite
[[nodiscard]] constexpr bool writesContents(Access a) noexcept { return a != Access::Read; }  ///< Write or ReadWrite

/// The graph-file spellings ("ReadWrite", "ColorAttachment", "sampled"); the views point to
/// static storage. A value outside the enum gives "?".
[[nodiscard]] std::string_view toString(Access a) noexcept;
[[nodiscard]] std::string_view toString(Stage s) noexcept;
[[nodiscard]] std::string_view toString(BindAs a) noexcept;
/// The inverse of toString; nullopt for an unknown name. `s` is read during the call only.
/// parseBindAs() also gives nullopt for "default", which files cannot spell.
[[nodiscard]] std::optional<Access> parseAccess(std::string_view s) noexcept;
[[nodiscard]] std::optional<Stage> parseStage(std::string_view s) noexcept;
[[nodiscard]] std::optional<BindAs> parseBindAs(std::string_view s) noexcept;

/// "Access@Stage", as written in graph files (with " as Binding" unless Default).
[[nodiscard]] std::string toString(const UsageMode& u);
[[nodiscard]] inline std::string toString(const Usage& u) { return toString(u.mode()); }

/// The `as` a usage gets when the file leaves it out (docs/graph-format.md, "Usages"): for a
/// shader stage, storage for buffers and image writes, sampled for image reads; other stages
/// keep Default. The loader resolves every usage it reads; GraphDescs built in code may leave
/// it to this.
[[nodiscard]] constexpr BindAs resolvedBinding(const UsageMode& u, bool image) noexcept {
    if (u.as != BindAs::Default || !isShaderStage(u.stage)) return u.as;
    if (!image) return BindAs::Storage;
    return u.access == Access::Read ? BindAs::Sampled : BindAs::Storage;
}

}  // namespace skygraph
