// The graph file format's limits, which the loader and the load-time checks share.
#pragma once

#include <cstdint>

namespace skygraph {

/// The largest image extent a file may give (the common maxImageDimension2D; devices may allow
/// less); extents, mip counts and mip ranges are bounded by it.
inline constexpr uint32_t kMaxImageExtent = 16384;

}  // namespace skygraph
