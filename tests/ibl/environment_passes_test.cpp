// graphs/ibl.json as shipped, on lavapipe under validation, with an analytic environment:
// the cube, its mip chain, irradiance, GGX prefilter and BRDF table against the double
// references of tests/support/ibl_math.hpp.
#include "analytic_environment.hpp"
#include "executor_test_util.hpp"

#include <skygraph/pass.hpp>

#include <map>

namespace skygraph::test {
namespace {

const std::filesystem::path kSource = SKYGRAPH_SOURCE_DIR;
constexpr uint32_t kEquirectWidth = 512, kEquirectHeight = 256;

/// Every product of graphs/ibl.json for `radiance`, read back mip-major, layer-minor.
std::map<std::string, std::vector<ImageData>> runIblGraph(Dir (*radiance)(const Dir&)) {
    const PassLibrary library = PassLibrary::withBuiltins();
    GraphDesc graph = loadGraphFile(kSource / "graphs/ibl.json", library.registry());
    for (auto& r : graph.resources)
        if (r.name == "equirect") r.extent = Extent{false, 1, kEquirectWidth, kEquirectHeight};
    CompileOptions co;
    co.presentReplacement = ExternalState::TransferSrc;
    co.outputWidth = co.outputHeight = 16;
    RendererOptions ro;
    ro.passes = &library;
    ro.framesInFlight = 1;
    Renderer renderer(sharedDevice(), CompiledGraph(std::move(graph), co), ro);
    renderer.setExternalImage("equirect", equirectImage(radiance, kEquirectWidth, kEquirectHeight));
    renderer.renderFrame();
    std::map<std::string, std::vector<ImageData>> out;
    for (const char* name : {"environment", "irradiance", "prefiltered", "brdf_lut"}) out[name] = renderer.readImage(name);
    return out;
}

class EnvironmentPasses : public ExecutorTest {
protected:
    static void SetUpTestSuite() { products_ = runIblGraph(sunSky); }
    static void TearDownTestSuite() { products_.clear(); }
    static std::map<std::string, std::vector<ImageData>> products_;
};
std::map<std::string, std::vector<ImageData>> EnvironmentPasses::products_;

TEST_F(EnvironmentPasses, MipChainIsTheBoxMeanOfTheLevelAbove) {
    const auto& env = products_.at("environment");
    ASSERT_EQ(env.size(), 9u * 6u) << "256^2 with a full chain: 9 levels of 6 faces";
    double worst = 0.0;
    for (size_t mip = 1; mip < 9; ++mip)
        for (size_t face = 0; face < 6; ++face) {
            const ImageData& above = env[(mip - 1) * 6 + face];
            const ImageData& level = env[mip * 6 + face];
            ASSERT_EQ(level.width, 256u >> mip);
            for (uint32_t y = 0; y < level.height; ++y)
                for (uint32_t x = 0; x < level.width; ++x) {
                    const Dir mean = (texel(above, 2 * x, 2 * y) + texel(above, 2 * x + 1, 2 * y) +
                                      texel(above, 2 * x, 2 * y + 1) + texel(above, 2 * x + 1, 2 * y + 1)) / 4.0;
                    worst = std::max(worst, maxRelativeError(texel(level, x, y), mean));
                }
        }
    EXPECT_LT(worst, 2e-3) << "half-float storage rounds to ~1e-3";
}

TEST_F(EnvironmentPasses, CubeTexelsMatchTheAnalyticEnvironment) {
    const auto& env = products_.at("environment");
    double worst = 0.0;
    for (int face = 0; face < 6; ++face)
        for (uint32_t y = 1; y < 256; y += 17)
            for (uint32_t x = 3; x < 256; x += 13) {
                const Dir want = math::ibl::cubeTexelMean(sunSky, face, int(x), int(y), 256, 8);
                worst = std::max(worst, maxRelativeError(texel(env[size_t(face)], x, y), want));
            }
    EXPECT_LT(worst, 3e-3);  // measured 1.5e-3: equirect bilinear + half storage
}

TEST_F(EnvironmentPasses, IrradianceMatchesTheCosineConvolution) {
    const auto& irr = products_.at("irradiance");
    ASSERT_EQ(irr.size(), 6u);
    double worst = 0.0;
    for (int face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < 32; y += 5)
            for (uint32_t x = 0; x < 32; x += 5) {
                const Dir n = texelDirection(face, x, y, 32);
                worst = std::max(worst, maxRelativeError(texel(irr[size_t(face)], x, y),
                                                         math::ibl::irradianceOverPi(sunSky, n, 1u << 13)));
            }
    EXPECT_LT(worst, 0.015);  // measured 1.0e-2 with 1024 samples
}

TEST_F(EnvironmentPasses, PrefilteredMipsMatchTheGgxConvolutionOfTheirRoughness) {
    const auto& pre = products_.at("prefiltered");
    ASSERT_EQ(pre.size(), 6u * 6u);
    for (uint32_t mip = 0; mip < 6; ++mip) {
        const double roughness = mip / 5.0;  // mip / (mips - 1)
        const uint32_t size = 128u >> mip;
        double worst = 0.0;
        for (int face = 0; face < 6; ++face)
            for (uint32_t y = 0; y < size; y += std::max(1u, size / 6))
                for (uint32_t x = 0; x < size; x += std::max(1u, size / 5)) {
                    const Dir n = texelDirection(face, x, y, size);
                    // Mip 0 is the mirror: the environment's texel mean at that size.
                    const Dir want = mip == 0 ? math::ibl::cubeTexelMean(sunSky, face, int(x), int(y), int(size), 8)
                                              : math::ibl::prefilteredRadiance(sunSky, n, roughness, 4096);
                    worst = std::max(worst, maxRelativeError(texel(pre[mip * 6 + size_t(face)], x, y), want));
                }
        // Measured 0.2% (mirror) growing to 1.9% at roughness 1 (1024 samples).
        EXPECT_LT(worst, mip == 5 ? 0.03 : 0.015) << "mip " << mip << ", roughness " << roughness;
    }
}

TEST_F(EnvironmentPasses, BrdfTableMatchesTheSplitSumIntegral) {
    const auto& lut = products_.at("brdf_lut");
    ASSERT_EQ(lut.size(), 1u);
    ASSERT_EQ(lut[0].format, VK_FORMAT_R16G16_SFLOAT);
    double sameEstimator = 0.0, converged = 0.0;
    for (uint32_t j = 0; j < 128; j += 9)
        for (uint32_t i = 0; i < 128; i += 7) {
            const double nv = (i + 0.5) / 128, roughness = (j + 0.5) / 128;
            const auto got = lut[0].pixel(i, j);
            // The shader's own estimator (1024 samples, graphs/ibl.json) in double: only
            // float arithmetic and half storage differ.
            const auto same = math::ibl::brdfIntegral(nv, roughness, 1024);
            sameEstimator = std::max({sameEstimator, std::abs(got[0] - same.x), std::abs(got[1] - same.y)});
            const auto want = math::ibl::brdfIntegral(nv, roughness, 1u << 14);
            converged = std::max({converged, std::abs(got[0] - want.x), std::abs(got[1] - want.y)});
        }
    EXPECT_LT(sameEstimator, 2e-3);
    // 1024 samples leave ~1% at grazing n.v, where the GGX half-vector density fits the
    // integrand worst (docs/environment.md).
    EXPECT_LT(converged, 0.015);
}

}  // namespace
}  // namespace skygraph::test
