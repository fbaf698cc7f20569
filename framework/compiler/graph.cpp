#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

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

int32_t Plan::resourceIndex(std::string_view n) const noexcept {
    for (size_t i = 0; i < resources.size(); ++i)
        if (resources[i].name == n) return static_cast<int32_t>(i);
    return -1;
}

}  // namespace skygraph
