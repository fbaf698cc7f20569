// The references themselves (tests/support/ibl_math.hpp), on the CPU: the quasi-Monte
// Carlo integrals against closed forms, so the GPU tests measure against something right.
#include "analytic_environment.hpp"

#include <gtest/gtest.h>

namespace skygraph::test {
namespace {

using namespace math::ibl;

TEST(IblMath, IrradianceOfAPolynomialSkyMatchesTheSphericalHarmonicClosedForm) {
    for (const Dir n : {Dir(0, 1, 0), Dir(1, 0, 0), glm::normalize(Dir(0.3, -0.5, 0.8)), glm::normalize(Dir(-1, 1, -1))}) {
        const Dir got = irradianceOverPi(polynomialSky, n, 1u << 14);
        const Dir want = polynomialSkyIrradiance(n);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-4) << "normal " << n.x << "," << n.y << "," << n.z;
    }
}

TEST(IblMath, PrefilterKeepsConstantsAndTendsToTheMirrorAtLowRoughness) {
    const auto constant = [](const Dir&) { return Dir(2.0, 3.0, 4.0); };
    const Dir n = glm::normalize(Dir(0.2, 0.9, -0.3));
    for (double r : {0.1, 0.5, 1.0}) {
        const Dir p = prefilteredRadiance(constant, n, r, 4096);
        EXPECT_NEAR(p.y, 3.0, 1e-9);
    }
    const Dir mirror = prefilteredRadiance(sunSky, n, 0.02, 4096);
    EXPECT_LT(maxRelativeError(mirror, sunSky(n)), 1e-3);
    // Rougher lobes spread the sun: its peak falls as roughness grows.
    const Dir sun = glm::normalize(Dir(0.4, 0.6, -0.7));
    EXPECT_GT(prefilteredRadiance(sunSky, sun, 0.3).x, prefilteredRadiance(sunSky, sun, 0.6).x);
}

TEST(IblMath, BrdfIntegralIsBoundedAndMatchesKnownLimits) {
    // Smooth surface seen head-on: the whole lobe reflects, Fresnel at v.h = 1 is F0.
    const auto smooth = brdfIntegral(1.0, 0.02, 4096);
    EXPECT_NEAR(smooth.x, 1.0, 2e-3);
    EXPECT_NEAR(smooth.y, 0.0, 1e-3);
    for (double nv : {0.1, 0.5, 0.9})
        for (double r : {0.2, 0.6, 1.0}) {
            const auto ab = brdfIntegral(nv, r, 4096);
            EXPECT_GT(ab.x, 0.0);
            EXPECT_GE(ab.y, 0.0);
            EXPECT_LE(ab.x + ab.y, 1.0 + 1e-6) << "energy at n.v " << nv << ", roughness " << r;
        }
    // At roughness 1, GGX is uniform (D = 1/pi) and the visibility 0.5 / (n.l + n.v), so the
    // albedo A + B has the closed form 1 - n.v ln(1 + 1/n.v).
    for (double nv : {0.1, 0.5, 0.9}) {
        const auto ab = brdfIntegral(nv, 1.0, 1u << 14);
        EXPECT_NEAR(ab.x + ab.y, 1.0 - nv * std::log(1.0 + 1.0 / nv), 2e-3) << "n.v " << nv;
    }
}

}  // namespace
}  // namespace skygraph::test
