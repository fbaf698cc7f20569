// An equirect at another size: what lets a view re-bake a file of another size beside its
// frames (the running graph's equirect and products keep their sizes; a rebuild gives the
// file's own).
#pragma once

#include <skygraph/hdr_image.hpp>

#include <cstdint>

namespace skygraph::app {

/// `from` resampled to `width` x `height`, separably: where an axis shrinks, each texel is
/// the mean of the texels its footprint covers (by covered fraction), so the map's integral
/// over the sphere's rectangle, a sun's power included, is kept; where it grows, linear
/// interpolation between texel centres, wrapping around in longitude and clamped at the
/// poles. Both sizes at least 1.
[[nodiscard]] HdrImage resampleEquirect(const HdrImage& from, uint32_t width, uint32_t height);

}  // namespace skygraph::app
