#include "graph_limits.hpp"

#include <string>

namespace skygraph {

Diagnostics limitProblems(const GraphDesc& graph) {
    Diagnostics diags;
    for (const ResourceDesc& r : graph.resources) {
        const auto problem = [&](std::string what) { diags.add({graph.file, r.jsonPath(), "", r.name, std::move(what)}); };
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
        if (r.layers == 0 || r.layers > kMaxLayers)
            problem("layers must be between 1 and " + std::to_string(kMaxLayers) + ", not " + std::to_string(r.layers));
        if (r.mips > std::bit_width(kMaxImageExtent))
            problem("mips must be at most " + std::to_string(std::bit_width(kMaxImageExtent)) + " (0 for the full chain), not " +
                    std::to_string(r.mips));
    }
    return diags;
}

}  // namespace skygraph
