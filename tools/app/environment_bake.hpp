// Runs the environment pipeline (graphs/ibl.json) headless on one equirect image: the one bake
// path of the application. `skygraph render` bakes the products its frame graph imports and
// shares them with the frame's renderer; `skygraph cubemap` bakes the products asked for on a
// device of its own and reads them back (what bench/ibl_compare.sh measures).
#pragma once

#include <skygraph/device.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/hdr_image.hpp>
#include <skygraph/image_data.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/shading_math.hpp>
#include <skygraph/staging_buffer.hpp>

#include "staging_pool.hpp"

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace skygraph {
class PassLibrary;
}

namespace skygraph::app {

/// Called as a bake's steps finish ("compile", "upload", "passes", "read back"), e.g. for a
/// progress bar. May be empty.
using BakeStepCallback = std::function<void(const std::string& step)>;

/// An HDRI's pixels as the float RGBA image the graph's `equirect` is uploaded from.
[[nodiscard]] ImageData toImageData(HdrImage image);

/// An environment file as the bakes take it (loadHdrImage). Throws ImageError naming the file
/// when a pixel value is NaN or infinite: it would spread through every filtered product and
/// light the whole frame with it. Values past +-`largest`, the most the products hold
/// (math::kLargestHalf for half-float cubes), are clamped to it, with a warning, rather than
/// becoming infinite in the products; negative colour values are clamped to 0, with a warning.
/// An image that is not 2:1 is read as an equirect map all the same, with a warning.
[[nodiscard]] HdrImage loadEnvironmentImage(const std::filesystem::path& file, float largest = math::kLargestHalf);

/// One run of the environment graph. Owns the renderer, which owns the products.
struct EnvironmentBake {
    /// Holds the products: share them (Renderer::shareImage()) or read them back
    /// (Renderer::readImage()). Must not outlive the Device it was baked on.
    std::unique_ptr<Renderer> renderer;
    double setupMs = 0.0;  ///< compile, pipelines, upload
    double gpuMs = 0.0;    ///< the passes, submit to fence (wall clock)
};

/// Runs `graph` (graphs/ibl.json, sized and configured by the caller) once on `equirect`,
/// building only `products`: they are the compile's outputs (CompileOptions::outputs), so the
/// passes of the graph's other exports are culled. `equirect` sets the extent of the graph's
/// `equirect` and is uploaded to it (the renderer keeps its own copy). `passes` (the recording
/// code, e.g. PassLibrary::withBuiltins()) is borrowed for the renderer's life; `device` must
/// outlive the result. `shaders` (RendererOptions::shaderCompiler): the compiler whose kept
/// shader sources to build from, e.g. the last bake's (Renderer::shaderCompiler()), rather
/// than the files on disk. Throws GraphError / ExecutorError naming what is wrong, e.g. a
/// product the graph does not export.
[[nodiscard]] EnvironmentBake bakeEnvironment(Device& device, GraphDesc graph, const HdrImage& equirect,
                                              const std::set<std::string, std::less<>>& products,
                                              const PassLibrary* passes, const BakeStepCallback& onStep = {},
                                              std::shared_ptr<ShaderCompiler> shaders = nullptr);

/// Re-bakes the environment a frame renderer imports beside its frames, again and again
/// (docs/queues.md, "Background frames"). Two or three renderers of `graph` with its feature
/// `streamed_equirect` on are made once and take turns: the graph's own UploadPass copies the
/// equirect in on the transfer queue, and every other pass runs on the compute queue. A change
/// costs a submit, not a compile. Each bake is a background frame; the frames keep the
/// products they import until swapInWhenFinished() hands them the new ones. A bake reuses the
/// renderer swapped in longest ago: with two, the frames must sample only the last swap's
/// products; with three, also the swap's before (a sky fading from one to the other). Owns
/// the renderers (and so the products the frames sample after a swap); `device` and `passes`
/// must outlive it, and it must outlive the frames' use of its products. Not copyable.
class EnvironmentBaker {
public:
    /// Compiles `graph` for `products` with an equirect of `width` x `height` and makes
    /// `renderers` (2 or 3) renderers. `background` false: every pass runs on the graphics
    /// queue and start() waits for the bake (the synchronous way, for comparison).
    /// `shaders` as for bakeEnvironment(). Throws like bakeEnvironment(), and for a graph
    /// without the feature `streamed_equirect`.
    EnvironmentBaker(Device& device, GraphDesc graph, uint32_t width, uint32_t height,
                     std::set<std::string, std::less<>> products, const PassLibrary* passes, bool background = true,
                     uint32_t renderers = 2, std::shared_ptr<ShaderCompiler> shaders = nullptr);
    EnvironmentBaker(const EnvironmentBaker&) = delete;
    EnvironmentBaker& operator=(const EnvironmentBaker&) = delete;

    /// Starts baking the equirect in `pixels` (stagingBytes() of float RGBA texels, rows
    /// tightly packed, of the size given at construction; made with the baker's Device) with
    /// the renderer whose products the frames do not sample: stages it for that renderer's
    /// UploadPass and submits, waiting only for that renderer's last bake. The renderer holds
    /// `pixels` until its copy has run. False, starting nothing, while the previous bake is
    /// not swapped in yet. Throws ExecutorError for a buffer of another size.
    bool start(std::shared_ptr<const StagingBuffer> pixels);
    /// The same from pixels on the host: they are copied into a staging buffer of the baker's
    /// first (on the calling thread). Throws ExecutorError for an equirect of another size.
    bool start(const HdrImage& equirect);
    /// Bytes of the equirect a bake uploads: width x height x 16.
    [[nodiscard]] VkDeviceSize stagingBytes() const noexcept { return staging_.bufferBytes(); }
    /// Between two frames of `frame`: once the bake has finished on the GPU, imports its
    /// products into `frame` (Renderer::importImage, which neither waits nor rebuilds) and
    /// returns true; false while it runs or when none was started. Never blocks.
    bool swapInWhenFinished(Renderer& frame);
    [[nodiscard]] bool pending() const noexcept { return pending_; }
    /// Product `name` of the last bake swapped in (empty before the first swap).
    [[nodiscard]] SharedImage swappedIn(const std::string& name) const;
    /// Host time of the last start() on the calling thread: the copy to a staging buffer (from
    /// an HdrImage) and the submits.
    [[nodiscard]] double lastStartMs() const noexcept { return lastStartMs_; }

private:
    uint32_t width_ = 0, height_ = 0;
    StagingPool staging_;  ///< start(HdrImage)'s
    std::vector<std::unique_ptr<Renderer>> renderers_;
    std::set<std::string, std::less<>> products_;
    bool background_ = true;
    size_t next_ = 0;  ///< The renderer the next bake uses.
    std::optional<size_t> swapped_;  ///< The renderer last swapped in.
    bool pending_ = false;
    double lastStartMs_ = 0.0;
};

/// What `skygraph cubemap` bakes. Sizes are face sizes in texels. A plain value.
struct BakeOptions {
    std::string graphText;         ///< graphs/ibl.json's text.
    uint32_t size = 256;           ///< environment cube (full mip chain)
    uint32_t prefilteredSize = 0;  ///< prefiltered mip 0 (6 levels); 0: max(size / 2, 32)
    uint32_t supersample = 2;      ///< EquirectToCubemapPass taps per texel: N x N
    uint32_t samples = 1024;       ///< IrradiancePass and PrefilterPass samples per texel
    bool float32 = false;          ///< RGBA32F (and RG32F) products instead of 16-bit floats
    /// Products besides "environment": any of "irradiance", "prefiltered", "brdf_lut". Passes
    /// of products not asked for are culled, so they cost nothing.
    std::vector<std::string> products{"irradiance", "prefiltered", "brdf_lut"};
    std::string device;            ///< DeviceOptions::device
    bool validate = false;
    /// Called as the steps finish (load, compile, GPU, read back), e.g. for a progress bar.
    BakeStepCallback onStep;
};

/// Each product's levels, mip-major and face-minor (Renderer::readImage), plus timings. Owns
/// everything it holds: the device and renderer of the bake are gone.
struct BakeResult {
    std::map<std::string, std::vector<ImageData>> products;  ///< by resource name
    double setupMs = 0.0;  ///< device, compile, pipelines, upload
    double gpuMs = 0.0;    ///< the passes, submit to fence (wall clock)
    uint32_t validationMessages = 0;
    std::vector<PassTiming> passTimings;  ///< GPU timestamps per pass
};

/// Bakes `equirect` with the built-in passes on a device of its own (bakeEnvironment()) and
/// reads every level of the environment cube and of each product back. Throws GraphError /
/// ExecutorError / std::invalid_argument with a message naming what is wrong (e.g. an
/// unknown product).
[[nodiscard]] BakeResult bakeAndReadBack(const HdrImage& equirect, const BakeOptions& options);

}  // namespace skygraph::app
