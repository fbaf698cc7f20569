// Runs the environment pipeline (graphs/ibl.json) headless on one equirect image and reads
// back the products: what `skygraph cubemap` writes, and what bench/ibl_* measures.
#pragma once

#include <skygraph/executor.hpp>
#include <skygraph/hdr_image.hpp>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace skygraph::cli {

/// What to bake. Sizes are face sizes in texels.
struct BakeOptions {
    std::string graphText;         ///< graphs/ibl.json's text.
    uint32_t size = 256;           ///< environment cube (full mip chain)
    uint32_t prefilteredSize = 0;  ///< prefiltered mip 0 (6 levels); 0: max(size / 2, 32)
    uint32_t supersample = 2;      ///< EquirectToCubemapPass taps per texel: N x N
    uint32_t samples = 1024;       ///< IrradiancePass and PrefilterPass samples per texel
    bool float32 = false;          ///< RGBA32F (and RG32F) products instead of 16-bit floats
    /// Products besides "environment": any of "irradiance", "prefiltered", "brdf_lut". Passes
    /// of products not asked for are removed before compiling, so they cost nothing.
    std::vector<std::string> products{"irradiance", "prefiltered", "brdf_lut"};
    std::string device;            ///< DeviceOptions::device
    bool validate = false;
    /// Called as the steps finish (load, compile, GPU, read back), e.g. for a progress bar.
    std::function<void(const std::string& step)> onStep;
};

/// Each product's levels, mip-major and face-minor (Renderer::readImage), plus timings.
struct BakeResult {
    std::map<std::string, std::vector<ImageData>> products;  ///< by resource name
    double setupMs = 0.0;  ///< device, compile, pipelines, upload
    double gpuMs = 0.0;    ///< the passes, submit to fence (wall clock)
    uint32_t validationMessages = 0;
    std::vector<PassTiming> passTimings;  ///< GPU timestamps per pass
};

/// Bakes `equirect`. Throws GraphError / ExecutorError / std::invalid_argument with a message
/// naming what is wrong (e.g. an unknown product).
[[nodiscard]] BakeResult bakeEnvironment(const HdrImage& equirect, const BakeOptions& options);

}  // namespace skygraph::cli
