// Which usages a resource can have: a buffer is never an attachment, a sampled image is only
// read, an attachment renders to one mip level. The loader refuses a file's usage that does not
// fit with a message; compile() refuses a GraphDesc built in code the same way, found in its
// index's walk over the usages through a table of every case built with skygraph.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/usage.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace skygraph {

/// What the rules ask of the resource a usage touches.
struct UsageSubject {
    bool image = false;
    bool depthStencil = false;    ///< Its format has depth or stencil.
    bool storageCapable = false;  ///< Its format can be a storage image.
    bool severalLevels = false;   ///< The usage touches more than one mip level.
};

/// Whether `"mips": "full"` of `r` is one level whatever the output: a fixed 1x1 extent.
[[nodiscard]] inline bool fullChainIsOneLevel(const ResourceDesc& r) noexcept {
    return !r.extent.relativeToOutput && r.mipCount(1, 1) == 1;
}

/// `resource` as usages of `range` (nullopt: the whole resource) touch it.
[[nodiscard]] inline UsageSubject usageSubject(const ResourceDesc& r, const std::optional<SubresourceRange>& range) noexcept {
    return {r.isImage(), r.format.isDepthStencil(), r.format.storageCapable,
            range ? range->mipCount != 1 : r.mips != 1 && !(r.mips == 0 && fullChainIsOneLevel(r))};
}

/// Why a usage does not fit its resource, or Fits.
enum class UsageMisfit : uint8_t {
    Fits,
    UnknownValue,  ///< An access, stage or binding outside its enum (only code can make one).
    IndexOutsideVertexInput,
    AsOutsideShaders,
    BufferAttachment,
    DepthFormatAsColor,
    ColorFormatAsDepth,
    AttachmentOfSeveralLevels,
    ImageAsVertexInput,
    VertexInputWrites,
    SampledBuffer,
    SampledWrite,
    UniformImage,
    UniformWrite,
    StorageFormat,
};

inline constexpr size_t kAccesses = 3, kStages = 8, kBindings = 5;

[[nodiscard]] constexpr UsageMisfit usageMisfit(const UsageSubject& r, const UsageMode& u) noexcept {
    if (size_t(u.access) >= kAccesses || size_t(u.stage) >= kStages || size_t(u.as) >= kBindings)
        return UsageMisfit::UnknownValue;
    if (u.as == BindAs::Index && u.stage != Stage::VertexInput) return UsageMisfit::IndexOutsideVertexInput;
    if (u.as != BindAs::Default && u.as != BindAs::Index && !isShaderStage(u.stage)) return UsageMisfit::AsOutsideShaders;
    if (isAttachmentStage(u.stage)) {
        if (!r.image) return UsageMisfit::BufferAttachment;
        if (u.stage == Stage::ColorAttachment && r.depthStencil) return UsageMisfit::DepthFormatAsColor;
        if (u.stage == Stage::DepthAttachment && !r.depthStencil) return UsageMisfit::ColorFormatAsDepth;
        if (r.severalLevels) return UsageMisfit::AttachmentOfSeveralLevels;
    }
    if (u.stage == Stage::VertexInput || u.stage == Stage::Indirect) {
        if (r.image) return UsageMisfit::ImageAsVertexInput;
        if (u.access != Access::Read) return UsageMisfit::VertexInputWrites;
    }
    if (isShaderStage(u.stage)) {
        const BindAs as = resolvedBinding(u, r.image);
        if (as == BindAs::Sampled && !r.image) return UsageMisfit::SampledBuffer;
        if (as == BindAs::Sampled && u.access != Access::Read) return UsageMisfit::SampledWrite;
        if (as == BindAs::Uniform && r.image) return UsageMisfit::UniformImage;
        if (as == BindAs::Uniform && u.access != Access::Read) return UsageMisfit::UniformWrite;
        if (as == BindAs::Storage && r.image && !r.storageCapable) return UsageMisfit::StorageFormat;
    }
    return UsageMisfit::Fits;
}

/// Empty when the usage fits the resource; otherwise why not, in words that name the expected
/// usage (e.g. a depth format used as a color attachment).
[[nodiscard]] std::string usageProblem(const ResourceDesc& resource, const Usage& usage);

/// Empty when a pass on `queue` can perform `usage` of `resource`; otherwise why not, naming
/// the queue it needs (a copy of a depth or stencil image needs graphics).
[[nodiscard]] std::string queueProblem(QueueKind queue, const ResourceDesc& resource, const Usage& usage);

namespace detail {
/// Per usage mode (stage << 5 | access << 3 | as, for stage and as below 8 and access below 4;
/// usageFits refuses larger values before it looks), the rows (fitRow below) it fits as a
/// 16-bit mask; 0 where a value is outside its enum.
extern const std::array<uint16_t, 256> kFitRows;
}  // namespace detail

/// A subject as a row of the table; kept per resource, with severalLevels for all of it.
enum class FitRow : uint8_t {};
[[nodiscard]] constexpr FitRow fitRow(const UsageSubject& r) noexcept {
    return FitRow(uint8_t(r.image) | uint8_t(r.depthStencil) << 1 | uint8_t(r.storageCapable) << 2 |
                  uint8_t(r.severalLevels) << 3);
}
/// `row` for a usage of `levels` mip levels instead of the whole resource.
[[nodiscard]] constexpr FitRow withLevels(FitRow row, uint32_t levels) noexcept {
    return FitRow((uint8_t(row) & 7) | uint8_t(levels != 1) << 3);
}
/// usageMisfit(...) == Fits, as a lookup: the compiler asks it of every usage of a graph.
[[nodiscard]] inline bool usageFits(FitRow row, const UsageMode& u) noexcept {
    const auto stage = uint32_t(u.stage), access = uint32_t(u.access), as = uint32_t(u.as);
    if (((stage | as) >> 3 | access >> 2) != 0) return false;
    return (detail::kFitRows[stage << 5 | access << 3 | as] >> uint32_t(row)) & 1;
}

}  // namespace skygraph
