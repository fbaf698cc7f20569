// The graph format's limits (docs/graph-format.md, "Limits and defaults"): the loader refuses
// a file past them, and compile() a GraphDesc built in code.
#pragma once

#include "format_table.hpp"

#include <skygraph/diagnostics.hpp>
#include <skygraph/graph.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

namespace skygraph {

/// The largest image extent a file may give (the common maxImageDimension2D; devices may allow
/// less); extents, mip counts and mip ranges are bounded by it.
inline constexpr uint32_t kMaxImageExtent = 16384;
inline constexpr uint32_t kMaxLayers = 2048;
inline constexpr uint32_t kMaxDivisor = 4096;  ///< Of "output/N".
inline constexpr uint64_t kMaxBufferBytes = 1ull << 31;
/// The largest graph file loadGraphFile() reads (a 100,000-pass graph is about 20 MiB).
inline constexpr uint64_t kMaxGraphFileBytes = 256ull << 20;
/// What one subpass of a render pass can hold, on every device: the compiler places no
/// device's limit, but a pass past these renders nowhere. One depth attachment besides.
inline constexpr size_t kMaxColorAttachments = 8;  // maxColorAttachments of current GPUs

/// Why a pass's `nth` colour attachment (past kMaxColorAttachments) is refused.
[[nodiscard]] std::string extraColorAttachmentProblem(size_t nth);
/// Why a pass's second depth attachment is refused; `first` is the first one's JSON path.
[[nodiscard]] std::string secondDepthAttachmentProblem(const std::string& first);

/// Whether a presented image has a swapchain image's shape: a 2D image of a colour format,
/// one layer, one mip.
[[nodiscard]] inline bool presentable(const ResourceDesc& r) noexcept {
    return r.type == ResourceType::Image2D && !r.format.isDepthStencil() && r.mips == 1;
}

/// Why `r` (presented, an image) is not presentable(), as the loader and compile() say it.
[[nodiscard]] std::string unpresentableShape(const ResourceDesc& r);

/// Whether `s` names an image layout (Present, TransferSrc), which a buffer cannot be in.
[[nodiscard]] inline bool imageLayoutState(ExternalState s) noexcept {
    return s == ExternalState::Present || s == ExternalState::TransferSrc;
}

/// Whether `r` is an external resource that the frame exports in another state than it
/// arrives in: the renderer keeps it for the next frame as this one leaves it, in its `final`
/// state, so the next frame would not find it in its `initial` one. Present too (an image
/// arriving as presented and left in another layout was found in that one next frame), as
/// `presentReplacement` replaces it (CompileOptions::presentReplacement; a file's is Present).
[[nodiscard]] inline bool handedBackChanged(const ResourceDesc& r, ExternalState presentReplacement) noexcept {
    const auto replaced = [&](ExternalState s) { return s == ExternalState::Present ? presentReplacement : s; };
    return r.external && r.initial != ExternalState::None && r.isExported() && replaced(r.initial) != replaced(r.final);
}

/// What is wrong with a resource handedBackChanged() refuses, for messages.
[[nodiscard]] std::string handedBackProblem(const ResourceDesc& r);

/// Whether `r`'s type, states and sharing are values of their enums (a code-built GraphDesc
/// can hold any byte there).
[[nodiscard]] inline bool enumsFit(const ResourceDesc& r) noexcept {
    return r.type <= ResourceType::Buffer && r.initial <= ExternalState::General && r.final <= ExternalState::General &&
           r.sharing <= Sharing::Concurrent;
}

/// What is wrong with a resource's states, as the loader requires them of a file: only an
/// external image of a swapchain image's shape is presented, only an external resource
/// arrives in a state and it always does (the loader gives one where a file gives none), an
/// external one is not cleared, a buffer is never left for presentation or a copy source, an
/// exported external arrives as it leaves, and only images clear, to a value of their
/// format's kind that it holds (clearFits()). The first that applies, in this order.
enum class StatesProblem : uint8_t {
    None,
    PresentedNotExternal,
    Unpresentable,
    InitialNotExternal,
    ExternalWithoutInitial,
    ExternalCleared,
    BufferCleared,
    BufferInImageLayout,
    HandedBackChanged,
    ClearOfOtherKind,
    ClearOutOfRange,
};

/// Whether `r`'s clear holds values its format takes as given: a colour within
/// format_table::clearColorRange() (integers for the integer formats), a depth in [0, 1], a
/// stencil of 8 bits. NaN fits nowhere. A format without a range is named on its own.
[[nodiscard]] inline bool clearFits(const ResourceDesc& r) noexcept {
    const ClearValue& c = *r.clear;
    if (c.isDepth) return c.depth >= 0.0f && c.depth <= 1.0f && c.stencil <= 255;
    const format_table::ClearColorRange range = format_table::clearColorRange(r.format.format);
    if (range.empty()) return true;
    return std::all_of(c.color.begin(), c.color.end(), [&](float v) { return range.holds(v, std::trunc(v) == v); });
}

/// Why a clear value outside its format's range is refused, as messages say it.
inline constexpr std::string_view kClearOutsideRange = "a clear would not write any other value as given";

/// "[0, 1]", "[-65504, 65504]": a range as messages give it.
[[nodiscard]] std::string clearRangeText(const format_table::ClearColorRange& range);

[[nodiscard]] inline StatesProblem statesProblem(const ResourceDesc& r, ExternalState presentReplacement) noexcept {
    if (r.final == ExternalState::Present && !r.external) return StatesProblem::PresentedNotExternal;
    if (r.final == ExternalState::Present && r.isImage() && !presentable(r)) return StatesProblem::Unpresentable;
    if (!r.external && r.initial != ExternalState::None) return StatesProblem::InitialNotExternal;
    if (r.external && r.initial == ExternalState::None) return StatesProblem::ExternalWithoutInitial;
    if (r.external && r.clear) return StatesProblem::ExternalCleared;
    if (!r.isImage() && r.clear) return StatesProblem::BufferCleared;
    if (!r.isImage() && (imageLayoutState(r.initial) || imageLayoutState(r.final)))
        return StatesProblem::BufferInImageLayout;
    if (handedBackChanged(r, presentReplacement)) return StatesProblem::HandedBackChanged;
    if (r.clear && r.clear->isDepth != r.format.isDepthStencil()) return StatesProblem::ClearOfOtherKind;
    if (r.clear && !clearFits(r)) return StatesProblem::ClearOutOfRange;
    return StatesProblem::None;
}

[[nodiscard]] inline bool statesFit(const ResourceDesc& r, ExternalState presentReplacement) noexcept {
    return statesProblem(r, presentReplacement) == StatesProblem::None;
}

/// Whether `r`'s extent, layers, mip count and size are within the limits, and its shape and
/// states are as the loader allows (a code-built GraphDesc has not been through it); the index
/// asks once per resource, so only a resource past them costs a message.
[[nodiscard]] inline bool withinLimits(const ResourceDesc& r, ExternalState presentReplacement) noexcept {
    if (!enumsFit(r)) return false;
    if (!r.isImage()) return r.sizeBytes != 0 && r.sizeBytes <= kMaxBufferBytes && statesFit(r, presentReplacement);
    const Extent& e = r.extent;
    const bool extent = e.relativeToOutput ? e.divisor != 0 && e.divisor <= kMaxDivisor
                                           : e.width != 0 && e.height != 0 && e.width <= kMaxImageExtent &&
                                                 e.height <= kMaxImageExtent;
    const bool shape = r.type == ResourceType::Cube    ? r.layers == 6 && !e.relativeToOutput && e.width == e.height
                       : r.type == ResourceType::Image2D ? r.layers == 1
                                                         : true;
    // The compiler takes an image's aspects and size from its FormatInfo, which one put
    // together in code can make disagree with its VkFormat.
    return extent && shape && formatInfoMatches(r.format) && r.layers != 0 && r.layers <= kMaxLayers &&
           r.mips <= std::bit_width(kMaxImageExtent) && statesFit(r, presentReplacement);
}

/// A diagnostic for each resource of `graph` that withinLimits() refuses, naming it and what
/// is wrong.
[[nodiscard]] Diagnostics limitProblems(const GraphDesc& graph, ExternalState presentReplacement);

}  // namespace skygraph
