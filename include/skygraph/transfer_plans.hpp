// Plans for the transfers around a frame's plan: the setup that gives external resources their
// first contents before the first frame, and the copy of an image to the host after frames
// have run. Like compile(), these are pure: every barrier they hold follows the same rules
// (docs/barriers.md), and the executor records them as it records a frame. `graph` must be the
// graph `frame` was compiled from; both are read during the call only.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <functional>
#include <set>
#include <span>
#include <string>
#include <string_view>

namespace skygraph {

struct SetupOptions {
    /// External images whose first mip (every layer) the application provides; the rest of
    /// the image is cleared first. An unknown name, a resource that is not external, a buffer,
    /// an image whose `initial` state is None (every frame discards its contents), or one that
    /// is also in `imports` is an error.
    std::set<std::string, std::less<>> uploads;
    /// External images that another renderer provides (Renderer::importImage): no setup.
    std::set<std::string, std::less<>> imports;
};

/// The steps that run once when `frame` (compiled from `graph`) is installed, before its first
/// frame: each external resource that the frame finds in an `initial` state gets defined
/// contents, as steps of type Clear (an image: its `clear` value, else mid grey; depth: its
/// clear depth, else 1) and Upload (an image's first mip from the application; a buffer: the
/// executor's fill pattern), and the final barriers leave each resource in the layout the frame
/// expects it to arrive in, visible to the frame's first use. Images whose `initial` is None
/// need nothing: the frame discards their contents. Returns a plan of the same graph whose
/// resources are a subset of the frame's (by name and `decl`). Throws GraphError for a bad
/// `uploads` name, naming the file and resource. The result views `frame`'s name tables and
/// holds its own share of them: it stays valid on its own.
[[nodiscard]] Plan planSetup(const GraphDesc& graph, const Plan& frame, const SetupOptions& options = {});

/// The steps that copy every mip and layer of image `resource` to the host once the frames of
/// `frame` have finished: one step of type Readback, the barrier into TRANSFER_SRC_OPTIMAL
/// before it, and final barriers that return an external image to the layout the next frame
/// expects and make the copy visible to the host. Throws GraphError when `resource` is not an
/// image that `frame` leaves written (a buffer, unknown, or unused by the plan). Like
/// planSetup's, the result holds its own share of `frame`'s name tables.
[[nodiscard]] Plan planImageRead(const GraphDesc& graph, const Plan& frame, std::string_view resource);

/// An image that the application fills from the host once and then samples, e.g. a model's
/// texture: 2D, one layer, a full mip chain.
struct SampledImageShape {
    std::string name;  ///< unique among the images of one call; names the steps
    FormatInfo format;
    uint32_t width = 0, height = 0;
};

/// The steps that fill sampled images outside any frame's graph: per image, an Upload of mip 0
/// (every image arrives UNDEFINED), a Downsample of each further mip from the one above, and
/// final barriers that leave every mip in SHADER_READ_ONLY_OPTIMAL, visible to the sampled
/// reads of later fragment and compute shaders (the ShaderRead external state). The plan's graph is made for it (one external image per
/// shape, in order). Throws GraphError for an empty list, a repeated or bad name, a format the
/// executor cannot fill from RGBA (depth, stencil), a FormatInfo that is not findFormat()'s for
/// its format, or a zero or too large size.
[[nodiscard]] Plan planSampledImageUploads(std::span<const SampledImageShape> images);

}  // namespace skygraph
