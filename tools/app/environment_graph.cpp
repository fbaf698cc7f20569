// Sizing the environment pipeline's graphs: see environment_graph.hpp.
#include "environment_graph.hpp"

#include "shipped_names.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace skygraph::app {
namespace {

using namespace shipped;

ResourceDesc* findCube(GraphDesc& graph, std::string_view name) {
    for (ResourceDesc& r : graph.resources)
        if (r.name == name && r.type == ResourceType::Cube) return &r;
    return nullptr;
}

/// The power of two at or above `texels` (a real number of texels), at least 1.
uint32_t powerOfTwoAtLeast(double texels) {
    if (!(texels > 1.0)) return 1;  // also NaN
    if (texels >= double(1u << 31)) return 1u << 31;
    return std::bit_ceil(uint32_t(std::ceil(texels)));
}

/// The smallest face that keeps a texel in each of a cube's declared levels ("full", 0, needs one).
uint32_t smallestFaceFor(const ResourceDesc& cube) {
    const uint32_t levels = std::max(cube.mips, 1u);
    return levels >= 32 ? (1u << 31) : (1u << (levels - 1));
}

}  // namespace

uint32_t viewEnvironmentFaceSize(uint32_t outputHeight, double fovYDeg, uint32_t equirectWidth,
                                 uint32_t cap) noexcept {
    // Near 0 degrees the view needs ever more texels: the cap and the equirect bound it.
    const double fov = std::clamp(std::isnan(fovYDeg) ? 60.0 : fovYDeg, 1e-6, 179.999) * std::numbers::pi / 180.0;
    const uint32_t forView = powerOfTwoAtLeast(double(std::max(outputHeight, 1u)) / std::tan(fov / 2.0));
    const uint32_t forSource = powerOfTwoAtLeast(double(std::max(equirectWidth, 1u)) / std::numbers::pi);
    return std::max(std::min({forView, forSource, cap}), 1u);
}

uint32_t sequenceEquirectWidth(uint32_t faceSize, uint32_t sourceWidth) noexcept {
    const uint64_t wanted = uint64_t(faceSize) * 8;
    return uint32_t(std::min<uint64_t>(wanted, sourceWidth));
}

std::optional<EnvironmentSizes> viewEnvironmentSizes(const GraphDesc& frameGraph, uint32_t outputHeight,
                                                     double fovYDeg, uint32_t equirectWidth) {
    const ResourceDesc* environment = frameGraph.findResource(kEnvironment);
    if (!environment || environment->type != ResourceType::Cube || environment->extent.relativeToOutput)
        return std::nullopt;
    EnvironmentSizes sizes;
    sizes.environment = viewEnvironmentFaceSize(outputHeight, fovYDeg, equirectWidth, environment->extent.width);
    sizes.boundBySource =
        sizes.environment < viewEnvironmentFaceSize(outputHeight, fovYDeg, ~0u, environment->extent.width);
    sizes.prefiltered = sizes.environment / 2;
    if (const ResourceDesc* prefiltered = frameGraph.findResource(kPrefiltered);
        prefiltered && !prefiltered->extent.relativeToOutput)
        sizes.prefiltered = std::max(std::min(sizes.prefiltered, prefiltered->extent.width), smallestFaceFor(*prefiltered));
    sizes.prefiltered = std::max(sizes.prefiltered, 1u);
    return sizes;
}

EnvironmentSizes sizesForEnvironmentGraph(EnvironmentSizes sizes, const GraphDesc& frameGraph,
                                          const GraphDesc& environmentGraph) {
    if (frameGraph.findResource(kPrefiltered)) return sizes;  // the size both import and export
    if (const ResourceDesc* prefiltered = environmentGraph.findResource(kPrefiltered))
        sizes.prefiltered = std::max(sizes.prefiltered, smallestFaceFor(*prefiltered));
    return sizes;
}

void resizeEnvironmentGraph(GraphDesc& graph, const EnvironmentSizes& sizes) {
    for (std::string_view name : {kEnvironment, kEnvironmentPrevious})
        if (ResourceDesc* r = findCube(graph, name)) r->extent = Extent{false, 1, sizes.environment, sizes.environment};
    if (ResourceDesc* r = findCube(graph, kPrefiltered)) r->extent = Extent{false, 1, sizes.prefiltered, sizes.prefiltered};

    const auto isMip = [](const PassDesc& p) { return p.type == kCubemapMipPass; };
    const auto first = std::find_if(graph.passes.begin(), graph.passes.end(), isMip);
    if (first == graph.passes.end()) return;
    const PassDesc model = *first;
    const auto at = first - graph.passes.begin();
    std::erase_if(graph.passes, isMip);
    std::vector<PassDesc> chain;
    for (uint32_t mip = 1; (sizes.environment >> mip) >= 1; ++mip) {
        PassDesc pass = model;
        pass.name = "environment_mip" + std::to_string(mip);
        for (UsageDecl& use : pass.uses) {
            if (!use.usage.range) continue;
            use.usage.range->baseMip = graph.slotName(use.slot) == kCubemapMipSourceSlot ? mip - 1 : mip;
        }
        chain.push_back(std::move(pass));
    }
    graph.passes.insert(graph.passes.begin() + at, chain.begin(), chain.end());
}

bool setEquirectExtent(GraphDesc& graph, uint32_t width, uint32_t height) {
    for (ResourceDesc& r : graph.resources) {
        if (r.name != kEquirect) continue;
        r.extent = Extent{false, 1, width, height};
        return true;
    }
    return false;
}

}  // namespace skygraph::app
