// Environments whose radiance is a known function of direction, and helpers that run the
// environment pipeline's passes on them, for the tests of tests/ibl and bench/ibl_*.
#pragma once

#include <skygraph/image_data.hpp>
#include "ibl_math.hpp"

#include <cmath>

namespace skygraph::test {

using math::ibl::Dir;

/// A low-order polynomial of direction (spherical-harmonic bands 0..2 only), positive
/// everywhere, so the irradiance is known in closed form: band l scales by 1, 2/3, 1/4.
inline Dir polynomialSky(const Dir& d) {
    return {1.0 + 0.6 * d.x + 0.3 * d.y * d.z, 1.0 + 0.4 * d.y + 0.3 * (d.x * d.x - d.z * d.z),
            0.7 - 0.3 * d.z + 0.1 * (3.0 * d.y * d.y - 1.0)};
}

/// The exact E(n) / pi of polynomialSky.
inline Dir polynomialSkyIrradiance(const Dir& n) {
    return {1.0 + 0.4 * n.x + 0.075 * n.y * n.z, 1.0 + 0.4 * 2.0 / 3.0 * n.y + 0.075 * (n.x * n.x - n.z * n.z),
            0.7 - 0.2 * n.z + 0.025 * (3.0 * n.y * n.y - 1.0)};
}

/// polynomialSky plus a bright, smooth "sun" lobe: exercises the prefilter's sharper end.
inline Dir sunSky(const Dir& d) {
    const Dir sun = glm::normalize(Dir(0.4, 0.6, -0.7));
    return polynomialSky(d) + Dir(6.0, 5.0, 4.0) * std::exp(40.0 * (glm::dot(d, sun) - 1.0));
}

/// An equirect image of `radiance` sampled at pixel centres (RGBA, alpha 1).
template <typename Radiance>
ImageData equirectImage(Radiance&& radiance, uint32_t width, uint32_t height) {
    ImageData image;
    image.width = width;
    image.height = height;
    image.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    image.rgba.resize(size_t(width) * height * 4);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const math::Vec2<double> uv((x + 0.5) / width, (y + 0.5) / height);
            const Dir c = radiance(math::equirectToDirection(uv));
            float* px = &image.rgba[(size_t(y) * width + x) * 4];
            px[0] = float(c.x), px[1] = float(c.y), px[2] = float(c.z), px[3] = 1.0f;
        }
    return image;
}

/// Texel (x, y) of a read-back face as a double vector.
inline Dir texel(const ImageData& face, uint32_t x, uint32_t y) {
    const auto p = face.pixel(x, y);
    return {p[0], p[1], p[2]};
}

/// The unit direction through texel (x, y) of a face of `size`.
inline Dir texelDirection(int face, uint32_t x, uint32_t y, uint32_t size) {
    return glm::normalize(math::cubeToDirection(face, math::Vec2<double>((x + 0.5) / size, (y + 0.5) / size)));
}

inline double maxRelativeError(const Dir& got, const Dir& want) {
    double e = 0.0;
    for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(got[c] - want[c]) / std::max(std::abs(want[c]), 1e-3));
    return e;
}

}  // namespace skygraph::test
