#include "graph_limits.hpp"

#include <cstdio>
#include <optional>
#include <sstream>
#include <string>

namespace skygraph {

std::string unpresentableShape(const ResourceDesc& r) {
    std::string is = r.type == ResourceType::Cube            ? "a cube"
                     : r.type == ResourceType::Image2DArray ? "an image2d_array"
                     : r.format.isDepthStencil()            ? "of the depth format " + std::string(r.format.name)
                                                            : "of " + (r.mips == 0 ? std::string("the full mip chain")
                                                                                   : std::to_string(r.mips) + " mips");
    return "a presented image is a swapchain's: an image2d of a color format with one mip, not " + is;
}

std::string handedBackProblem(const ResourceDesc& r) {
    return "an external resource is kept for the next frame as this frame leaves it, in its final state " +
           std::string(toString(r.final)) + ", so it must arrive in that state too, not " +
           std::string(toString(r.initial)) + ": give `initial` and `final` one state (to copy it out, read it back)";
}

std::string clearRangeText(const format_table::ClearColorRange& range) {
    char text[64];
    std::snprintf(text, sizeof text, "[%.9g, %.9g]", range.lowest, range.highest);
    return text;
}

namespace {

/// What a clear that clearFits() refuses holds, and what its format takes.
std::string clearProblem(const ResourceDesc& r) {
    const ClearValue& c = *r.clear;
    char text[160];
    if (c.isDepth) {
        std::snprintf(text, sizeof text, "its clear depth %.9g must be in [0, 1] and its stencil %u at most 255",
                      double(c.depth), c.stencil);
        return text;
    }
    const format_table::ClearColorRange range = format_table::clearColorRange(r.format.format);
    std::snprintf(text, sizeof text, "its clear color [%.9g, %.9g, %.9g, %.9g] must hold four ", double(c.color[0]),
                  double(c.color[1]), double(c.color[2]), double(c.color[3]));
    return text + std::string(range.integers ? "integers" : "numbers") + " in " + clearRangeText(range) +
           ", the range of the format " + std::string(r.format.name) + " (" + std::string(kClearOutsideRange) + ")";
}

/// How a FormatInfo that formatInfoMatches() refuses differs from the known one, if any.
std::string formatInfoProblem(const FormatInfo& f) {
    const std::optional<FormatInfo> known = findFormat(f.format);
    if (!known)
        return "its format, VkFormat " + std::to_string(int(f.format)) +
               ", is not one skygraph knows (knownFormats() lists them)";
    std::string differs;
    const auto field = [&](const char* name, auto given, auto is) {
        if (given == is) return;
        std::ostringstream text;
        text << std::boolalpha << name << " " << given << " where it is " << is;
        differs += (differs.empty() ? "" : ", ") + text.str();
    };
    field("name", '"' + std::string(f.name) + '"', '"' + std::string(known->name) + '"');
    field("bytesPerTexel", f.bytesPerTexel, known->bytesPerTexel);
    field("hasDepth", f.hasDepth, known->hasDepth);
    field("hasStencil", f.hasStencil, known->hasStencil);
    field("srgb", f.srgb, known->srgb);
    field("storageCapable", f.storageCapable, known->storageCapable);
    return "its FormatInfo disagrees with its format " + std::string(known->name) + ": " + differs +
           " (take it from findFormat())";
}

}  // namespace

std::string extraColorAttachmentProblem(size_t nth) {
    return "a pass renders to at most " + std::to_string(kMaxColorAttachments) +
           " colour attachments (the maxColorAttachments of current GPUs); this is its " + std::to_string(nth) + "th";
}

std::string secondDepthAttachmentProblem(const std::string& first) {
    return "a pass renders to one depth attachment, and " + first + " is its depth attachment";
}

Diagnostics limitProblems(const GraphDesc& graph, ExternalState presentReplacement) {
    Diagnostics diags;
    for (const ResourceDesc& r : graph.resources) {
        const auto problem = [&](std::string what) { diags.add({graph.file, r.jsonPath(), "", r.name, std::move(what)}); };
        if (!enumsFit(r)) {
            problem("its type (" + std::to_string(int(r.type)) + "), initial (" + std::to_string(int(r.initial)) +
                    ") and final (" + std::to_string(int(r.final)) + ") states or sharing (" +
                    std::to_string(int(r.sharing)) + ") hold a value outside its enum");
            continue;
        }
        switch (statesProblem(r, presentReplacement)) {
            case StatesProblem::None: break;
            case StatesProblem::PresentedNotExternal:
                problem("only an external image (the swapchain's) can be presented");
                break;
            case StatesProblem::Unpresentable: problem(unpresentableShape(r)); break;
            case StatesProblem::InitialNotExternal:
                problem("only external resources arrive in a state; its initial is " + std::string(toString(r.initial)));
                break;
            case StatesProblem::ExternalWithoutInitial:
                problem("an external resource arrives in a state: give it an initial (a graph file's default is its "
                        "final, else ShaderRead)");
                break;
            case StatesProblem::ExternalCleared:
                problem("an external resource arrives with contents; it is not cleared");
                break;
            case StatesProblem::BufferCleared: problem("a buffer cannot be cleared by the graph"); break;
            case StatesProblem::BufferInImageLayout:
                problem("a buffer cannot start or end as Present or TransferSrc, which are image layouts");
                break;
            case StatesProblem::HandedBackChanged: problem(handedBackProblem(r)); break;
            case StatesProblem::ClearOfOtherKind:
                problem(std::string(r.format.isDepthStencil() ? "the depth format " : "the color format ") +
                        std::string(r.format.name) + " clears to " +
                        (r.format.isDepthStencil() ? "a depth value, not a color" : "a color, not a depth value"));
                break;
            case StatesProblem::ClearOutOfRange: problem(clearProblem(r)); break;
        }
        if (!r.isImage()) {
            if (r.sizeBytes == 0 || r.sizeBytes > kMaxBufferBytes)
                problem("a buffer's size must be between 1 and " + std::to_string(kMaxBufferBytes) + " bytes, not " +
                        std::to_string(r.sizeBytes));
            continue;
        }
        const Extent& e = r.extent;
        if (e.relativeToOutput && (e.divisor == 0 || e.divisor > kMaxDivisor))
            problem("an output-relative extent's divisor must be between 1 and " + std::to_string(kMaxDivisor) +
                    ", not " + std::to_string(e.divisor));
        if (!e.relativeToOutput && (e.width == 0 || e.height == 0 || e.width > kMaxImageExtent || e.height > kMaxImageExtent))
            problem("a fixed extent must be between 1 and " + std::to_string(kMaxImageExtent) + " each way, not " +
                    std::to_string(e.width) + "x" + std::to_string(e.height));
        if (r.format.format == VK_FORMAT_UNDEFINED) problem("an image needs a format");
        else if (!formatInfoMatches(r.format)) problem(formatInfoProblem(r.format));
        if (r.type == ResourceType::Cube && (r.layers != 6 || e.relativeToOutput || e.width != e.height))
            problem("a cube has 6 layers of square faces of a fixed extent, not " + std::to_string(r.layers) +
                    " layer(s) " + (e.relativeToOutput ? "of the output's extent" : "of " + std::to_string(e.width) +
                                                                                          "x" + std::to_string(e.height)));
        if (r.type == ResourceType::Image2D && r.layers != 1)
            problem("an image2d has 1 layer, not " + std::to_string(r.layers) + "; use image2d_array");
        if (r.layers == 0 || r.layers > kMaxLayers)
            problem("layers must be between 1 and " + std::to_string(kMaxLayers) + ", not " + std::to_string(r.layers));
        if (r.mips > std::bit_width(kMaxImageExtent))
            problem("mips must be at most " + std::to_string(std::bit_width(kMaxImageExtent)) + " (0 for the full chain), not " +
                    std::to_string(r.mips));
    }
    return diags;
}

}  // namespace skygraph
