#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <stdexcept>
#include <string>

#include <algorithm>
#include <bit>

namespace skygraph {

std::array<uint32_t, 2> Extent::resolve(uint32_t outputWidth,
                                        uint32_t outputHeight) const noexcept {
    if (!relativeToOutput) return {width, height};
    return {std::max(1u, outputWidth / divisor), std::max(1u, outputHeight / divisor)};
}

uint32_t ResourceDesc::mipCount(uint32_t outputWidth, uint32_t outputHeight) const noexcept {
    if (mips != 0) return mips;
    auto [w, h] = extent.resolve(outputWidth, outputHeight);
    return static_cast<uint32_t>(std::bit_width(std::max(w, h)));
}

FeatureValues GraphDesc::defaultFeatures() const {
    FeatureValues out;
    for (const auto& f : features) out[f.name] = f.defaultValue;
    return out;
}

const ResourceDesc* GraphDesc::findResource(std::string_view n) const noexcept {
    for (const auto& r : resources)
        if (r.name == n) return &r;
    return nullptr;
}

SlotId GraphDesc::internSlot(std::string_view slot) {
    if (slot.empty()) return 0;
    // A graph has a few slot names (its pass types'), so a search beats a map.
    const auto it = std::find(slotNames.begin(), slotNames.end(), slot);
    if (it != slotNames.end()) return static_cast<SlotId>(it - slotNames.begin()) + 1;
    slotNames.emplace_back(slot);
    return static_cast<SlotId>(slotNames.size());
}

std::string GraphDesc::usageJsonPath(size_t pass, size_t use) const {
    const PassDesc& p = passes.at(pass);
    std::string path = p.jsonPath.empty() ? "passes[" + std::to_string(pass) + "]" : p.jsonPath;
    const uint32_t r = p.uses.at(use).resource;
    // A GraphDesc built in code may name a resource that is not there (compile() reports it).
    if (p.usesByName && r < resources.size()) return path + ".uses." + resources[r].name;
    return path + ".uses[" + std::to_string(use) + "]";
}

}  // namespace skygraph
