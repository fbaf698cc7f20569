// proceduralSkyEquirect: see procedural_environment.hpp.
#include "procedural_environment.hpp"

#include <skygraph/shading_math.hpp>

#include <algorithm>
#include <cmath>

namespace skygraph::app {

HdrImage proceduralSkyEquirect(const std::array<double, 3>& sunDirection, uint32_t width) {
    using namespace math;
    width = std::max(width, 2u);
    HdrImage image;
    image.width = width;
    image.height = width / 2;
    image.rgba.resize(size_t(image.width) * image.height * 4);
    // A texel spans at most its diagonal in angle (at the equator; less towards the poles in
    // longitude), so a texel whose centre is farther from the sun than the disc's radius plus
    // that diagonal cannot touch the disc.
    const double texelAngle = std::sqrt(2.0) * kPi<double> / image.height;
    const double discRadius = radians(0.6);
    const double cosReach = std::cos(std::min(discRadius + texelAngle, kPi<double>));
    const Vec3<double> sun = glm::normalize(Vec3<double>(sunDirection[0], sunDirection[1], sunDirection[2]));
    constexpr int kDiscSamples = 16;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            const auto at = [&](double sx, double sy) {
                return equirectToDirection(Vec2<double>(sx / image.width, sy / image.height));
            };
            const Vec3<double> centre = at(x + 0.5, y + 0.5);
            Vec3<double> radiance(0.0);
            if (glm::dot(centre, sun) < cosReach) {
                radiance = proceduralSky(centre, sun);
            } else {
                // Equal-area weights (sin theta) make this the footprint's mean radiance.
                double weights = 0.0;
                for (int j = 0; j < kDiscSamples; ++j)
                    for (int i = 0; i < kDiscSamples; ++i) {
                        const Vec3<double> d = at(x + (i + 0.5) / kDiscSamples, y + (j + 0.5) / kDiscSamples);
                        const double w = std::sqrt(std::max(0.0, 1.0 - d.y * d.y));
                        radiance += proceduralSky(d, sun) * w;
                        weights += w;
                    }
                radiance /= std::max(weights, 1e-12);
            }
            float* p = image.rgba.data() + (size_t(y) * image.width + x) * 4;
            p[0] = float(radiance.x);
            p[1] = float(radiance.y);
            p[2] = float(radiance.z);
            p[3] = 1.0f;
        }
    return image;
}

}  // namespace skygraph::app
