// The procedural sky as an environment image, so that it lights the scene through the same
// pipeline as a file (graphs/ibl.json: cube, irradiance, prefiltered specular, BRDF LUT).
#pragma once

#include <skygraph/hdr_image.hpp>

#include <array>
#include <cstdint>
#include <string>

namespace skygraph::app {

/// The equirect size the procedural sky is rendered at: 1024 x 512 (0.35 degrees a texel),
/// enough for the largest environment cube that graphs/raster.json imports (256 texels a
/// face: viewEnvironmentFaceSize() allows a cube of width / pi texels).
inline constexpr uint32_t kProceduralEquirectWidth = 1024;

/// math::proceduralSky() (the function the skybox and the path tracer evaluate) with its sun
/// towards the unit `sunDirection`, as a `width` x (width / 2) equirect. Each texel is the mean over its footprint: texels the sun's
/// disc may touch are averaged over 16 x 16 samples, so the disc's power survives at any
/// width; the rest of the sky is smooth enough for the texel centre. Width at least 2.
[[nodiscard]] HdrImage proceduralSkyEquirect(const std::array<double, 3>& sunDirection,
                                             uint32_t width = kProceduralEquirectWidth);

/// The sun of frame `frame` of proceduralSkySequence(): it circles the sky once in `frames`
/// frames at 25 degrees above the horizon, so every frame's sky differs from the last.
[[nodiscard]] std::array<double, 3> sequenceSunDirection(uint32_t frame, uint32_t frames);

/// Writes a time-lapse of the procedural sky, the test content of environment sequences:
/// frames 0 to `frames` - 1 of proceduralSkyEquirect(sequenceSunDirection(i, frames), width),
/// each to sequenceFrameFile(pattern, i) (.hdr or .exr), making the folder if need be. All
/// frames are replaced or none: a failure leaves every frame file as it was. Nothing large is
/// committed: tests and benchmarks write what they play. Throws ImageError.
void writeProceduralSkySequence(const std::string& pattern, uint32_t frames, uint32_t width);

}  // namespace skygraph::app
