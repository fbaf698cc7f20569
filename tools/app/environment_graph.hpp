// Sizing graphs/ibl.json (the environment pipeline) and the frame graph that imports its
// products. Pure graph edits: no device. `skygraph render` uses them to build only as much
// environment as the view can show; `skygraph cubemap` to bake at the sizes asked for.
#pragma once

#include <skygraph/graph.hpp>

#include <cstdint>
#include <optional>

namespace skygraph::app {

/// Face sizes of the environment cube and of the prefiltered cube's mip 0, in texels.
struct EnvironmentSizes {
    uint32_t environment = 256;
    uint32_t prefiltered = 128;
    /// The equirect's width set `environment`: a wider one would have given a larger cube
    /// (rather than the view or the frame graph's declared extent).
    bool boundBySource = false;

    friend bool operator==(const EnvironmentSizes&, const EnvironmentSizes&) = default;
};

/// The smallest power-of-two cube face size whose texel at a face's centre subtends no more
/// than a pixel at the centre of a view `outputHeight` pixels tall with vertical field of view
/// `fovYDeg` (texel 2/N radians, pixel 2 tan(fov/2)/H: N = H / tan(fov/2)), and no larger than
/// an equirect `equirectWidth` texels wide can fill (2 pi / W radians a texel: N = W / pi),
/// nor than `cap`. At least 1. Out-of-range arguments (fov outside (0, 180), zero sizes) are
/// clamped, never undefined.
[[nodiscard]] uint32_t viewEnvironmentFaceSize(uint32_t outputHeight, double fovYDeg, uint32_t equirectWidth,
                                               uint32_t cap) noexcept;

/// How wide a sequence's frames are uploaded for a cube of `faceSize` texels a side when the
/// sky samples the cube, not the equirect: 8 times the face size, so a face's 90 degrees of
/// the equator get 2 equirect texels for each cube texel, or the source's width when that is
/// less. A 6K frame for a 256-texel cube is uploaded at 2048 wide: 9 times fewer texels to
/// copy, hold and filter, for a cube that differs by what docs/performance.md measures.
[[nodiscard]] uint32_t sequenceEquirectWidth(uint32_t faceSize, uint32_t sourceWidth) noexcept;

/// The sizes a frame graph's environment products should have for a view: the cube as
/// viewEnvironmentFaceSize() with the graph's declared `environment` extent as the cap, and
/// the prefiltered cube at half of it (its mip 0 is the mirror, seen only on curved, hence
/// minified, surfaces), capped by its declared extent and never below 2^(mips - 1), so that
/// each of its declared roughness levels keeps a texel. nullopt when `frameGraph` declares
/// no `environment` cube.
[[nodiscard]] std::optional<EnvironmentSizes> viewEnvironmentSizes(const GraphDesc& frameGraph,
                                                                   uint32_t outputHeight, double fovYDeg,
                                                                   uint32_t equirectWidth);

/// `sizes` (`frameGraph`'s, from viewEnvironmentSizes()) for the environment graph that bakes
/// its products: where the frame graph declares no prefiltered cube, which would say how
/// large the one it imports is, the environment graph's is never below 2^(mips - 1) of its
/// own declared levels.
[[nodiscard]] EnvironmentSizes sizesForEnvironmentGraph(EnvironmentSizes sizes, const GraphDesc& frameGraph,
                                                        const GraphDesc& environmentGraph);

/// Sets the extents of `environment` and `prefiltered` in `graph` (either the environment
/// graph or a frame graph importing its products; resources it lacks are skipped), and
/// rebuilds the environment graph's mip chain: graphs/ibl.json writes one CubemapMipPass per
/// level of its declared cube; the first is copied once per level of the new size, in place.
/// References and pointers into `graph.passes` are invalid afterwards.
void resizeEnvironmentGraph(GraphDesc& graph, const EnvironmentSizes& sizes);

/// Sets the extent of `graph`'s `equirect` (the image a scene's environment file is loaded
/// into) to `width` x `height`, so that the plan's subresources match the image. False when
/// the graph has no such resource.
bool setEquirectExtent(GraphDesc& graph, uint32_t width, uint32_t height);

}  // namespace skygraph::app
