// Per-pass GPU time of a graph's frames through the framework (Renderer::lastTimings), with
// the bytes each pass must read and write, for gpu_frame_bench. Bench-only.
#pragma once

#include <skygraph/device.hpp>
#include <skygraph/renderer.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace skygraph::gpubench {

/// One graph at one output size.
struct FrameCase {
    std::filesystem::path graph;
    /// May be empty: the graph's default features, no scene data. A scene with an environment
    /// file has it loaded and its IBL products baked (graphs/ibl.json beside the graph) before
    /// the first frame, untimed, as `skygraph render` does.
    std::filesystem::path scene;
    /// Empty, or a variant: "unorm-swapchain" (the graph's `swapchain` becomes B8G8R8A8_UNORM,
    /// so TonemappingPass encodes sRGB in its shader) or "compute-tonemap" (the graph's feature
    /// compute_tonemap on: TonemappingComputePass writes an R8G8B8A8_UNORM storage target).
    std::string variant;
    /// When set, the Present target of the last frame is written here as PNG (a read-back copy
    /// then follows every frame, outside the pass timestamps): to compare variants' pictures.
    std::filesystem::path png;
    uint32_t width = 1920;
    uint32_t height = 1080;
    uint32_t warmupFrames = 20;
    uint32_t frames = 200;
    /// External images to fill with a procedural sky (e.g. graphs/ibl.json's "equirect"), at
    /// the extent and format the graph declares, before the first frame; names the graph does
    /// not have are skipped (FrameResult lists the ones used).
    std::vector<std::string> proceduralExternals;
};

/// One pass's GPU times over the measured frames (timestamps around the pass, after its
/// barriers, as Renderer::lastTimings() reports them).
struct PassResult {
    std::string pass;
    std::string type;
    double bytes = 0;     ///< Minimum bytes read plus written (see bytesOfPass in the .cpp).
    /// Each attachment's render-pass ops and format, e.g. "swapchain B8G8R8A8_SRGB DontCare/Store".
    std::string attachments;
    double medianMs = 0;
    double p10Ms = 0;
    double p90Ms = 0;
};

struct FrameResult {
    std::vector<PassResult> passes;
    /// The whole recorded plan (RendererAccess::recordInto) between two ALL_COMMANDS timestamps:
    /// passes and barriers (a Readback step only when a PNG is asked for), no per-pass timestamps.
    /// A plan on several queues: host time from renderFrame() to the end of waitIdle().
    double frameMedianMs = 0;
    bool hostTimed = false;  ///< frameMedianMs is the host time of a plan on several queues.
    uint32_t frames = 0;
    std::vector<std::string> culled;  ///< "name: reason"
    std::vector<std::string> proceduralExternals;  ///< Those of FrameCase's this graph has.
};

/// Renders `c.frames` frames after `c.warmupFrames`, waiting for each, with the built-in pass
/// implementations. Throws GraphError / ExecutorError / ImageError with the file named.
[[nodiscard]] FrameResult measureFrames(Device& device, const FrameCase& c);

}  // namespace skygraph::gpubench
