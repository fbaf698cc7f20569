// Sizing the environment for a view (tools/app/environment_graph.hpp): the cube face
// size against the pixel it must resolve, the shipped graphs resized and compiled, and the
// frame graph importing exactly what the environment graph exports. Pure: no device.
#include "app/environment_graph.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/pass_registry.hpp>

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <numbers>

namespace skygraph {
namespace {

using namespace app;

const std::filesystem::path kSource = SKYGRAPH_SOURCE_DIR;
constexpr double kPi = std::numbers::pi;

/// Angle subtended by the texel at a cube face's centre, and by the pixel at a view's centre.
double centreTexelAngle(uint32_t faceSize) { return 2.0 * std::atan(1.0 / faceSize); }
double centrePixelAngle(uint32_t height, double fovYDeg) {
    return 2.0 * std::atan(std::tan(fovYDeg * kPi / 360.0) / height);
}

TEST(EnvironmentSizing, FaceSizeIsTheSmallestPowerOfTwoThatResolvesTheCentrePixel) {
    constexpr uint32_t kNoCap = 1u << 20, kWideSource = 1u << 20;
    for (uint32_t height : {1u, 64u, 480u, 1080u, 2160u})
        for (double fov : {0.5, 10.0, 45.0, 60.0, 90.0, 120.0, 179.9}) {
            const uint32_t n = viewEnvironmentFaceSize(height, fov, kWideSource, kNoCap);
            ASSERT_TRUE(std::has_single_bit(n)) << n;
            // Small-angle: a texel spans 2/N, a pixel 2 tan(fov/2)/H; compare like for like.
            EXPECT_LE(2.0 / n, 2.0 * std::tan(fov * kPi / 360.0) / height * (1 + 1e-12))
                << "N=" << n << " is too coarse for H=" << height << " fov=" << fov;
            if (n > 1) {
                EXPECT_GT(2.0 / (n / 2), 2.0 * std::tan(fov * kPi / 360.0) / height)
                    << "N/2 would do for H=" << height << " fov=" << fov;
            }
            EXPECT_LE(centreTexelAngle(n), centrePixelAngle(height, fov) * 1.0001);
        }
    EXPECT_EQ(viewEnvironmentFaceSize(1080, 90.0, kWideSource, kNoCap), 2048u) << "1080 / tan 45 = 1080";
    EXPECT_EQ(viewEnvironmentFaceSize(64, 60.0, kWideSource, kNoCap), 128u) << "64 / tan 30 = 110.9";
}

TEST(EnvironmentSizing, TheSourceAndTheCapBoundTheSize) {
    // A 1024-wide equirect spans 2 pi in 1024 texels: a face (pi/2 wide) gets 256 of them.
    EXPECT_EQ(viewEnvironmentFaceSize(2160, 30.0, 1024, 1u << 20), 512u) << "1024 / pi = 326 -> 512";
    EXPECT_EQ(viewEnvironmentFaceSize(2160, 30.0, 1024, 256), 256u);
    EXPECT_EQ(viewEnvironmentFaceSize(2160, 30.0, 2, 256), 1u) << "a 2x1 equirect holds next to nothing";
}

TEST(EnvironmentSizing, ExtremeArgumentsStayDefinedAndSmall) {
    EXPECT_EQ(viewEnvironmentFaceSize(0, 60.0, 4096, 256), 2u) << "height 0 counts as 1: 1 / tan 30 = 1.7";
    EXPECT_EQ(viewEnvironmentFaceSize(1080, 0.0, 4096, 256), 256u) << "fov 0: the cap";
    EXPECT_EQ(viewEnvironmentFaceSize(1080, 180.0, 4096, 256), 1u) << "fov 180: a pixel spans ~half the sphere";
    EXPECT_EQ(viewEnvironmentFaceSize(1080, -5.0, 4096, 256), 256u);
    EXPECT_EQ(viewEnvironmentFaceSize(1080, std::nan(""), 4096, 1u << 20), 2048u) << "NaN: the default 60 degrees";
    EXPECT_EQ(viewEnvironmentFaceSize(1080, 60.0, 4096, 0), 1u);
}

class ShippedGraphs : public ::testing::Test {
protected:
    PassRegistry registry = PassRegistry::withBuiltins();
    GraphDesc raster = loadGraphFile(kSource / "graphs/raster.json", registry);
    GraphDesc ibl = loadGraphFile(kSource / "graphs/ibl.json", registry);

    static uint32_t extentOf(const Plan& plan, const GraphDesc& graph, std::string_view name) {
        const int32_t i = plan.resourceIndex(name);
        if (i < 0) return 0;
        return graph.resources[plan.resources()[size_t(i)].decl].extent.width;
    }
};

TEST_F(ShippedGraphs, ViewSizesAreCappedByTheDeclaredExtents) {
    // raster.json declares environment 256^2 (full chain) and prefiltered 128^2 with 6 levels.
    auto big = viewEnvironmentSizes(raster, 1080, 60.0, 4096);
    ASSERT_TRUE(big);
    EXPECT_EQ(*big, (EnvironmentSizes{256, 128}));
    auto small = viewEnvironmentSizes(raster, 64, 60.0, 4096);
    ASSERT_TRUE(small);
    EXPECT_EQ(*small, (EnvironmentSizes{128, 64}));
    auto tiny = viewEnvironmentSizes(raster, 4, 60.0, 4096);
    ASSERT_TRUE(tiny);
    EXPECT_EQ(tiny->environment, 8u);
    EXPECT_EQ(tiny->prefiltered, 32u) << "6 roughness levels need a 32^2 base";
    GraphDesc noEnvironment = raster;
    std::erase_if(noEnvironment.resources, [](const ResourceDesc& r) { return r.name == "environment"; });
    EXPECT_FALSE(viewEnvironmentSizes(noEnvironment, 64, 60.0, 4096));
}

// A frame graph that samples the environment cube but declares no prefiltered cube sizes the
// prefiltered cube at half the environment's, which for a small cube leaves ibl.json's six
// roughness levels without texels: the environment graph's own levels bound it, and it compiles.
TEST_F(ShippedGraphs, AFrameWithoutAPrefilteredCubeLeavesItsSizeToTheEnvironmentGraph) {
    GraphDesc frame = raster;
    std::erase_if(frame.resources, [](const ResourceDesc& r) { return r.name == "prefiltered"; });
    ResourceDesc* environment = nullptr;
    for (ResourceDesc& r : frame.resources)
        if (r.name == "environment") environment = &r;
    ASSERT_NE(environment, nullptr);
    environment->extent = Extent{false, 1, 8, 8};
    environment->mips = 1;
    const auto sizes = viewEnvironmentSizes(frame, 1080, 60.0, 4096);
    ASSERT_TRUE(sizes);
    EXPECT_EQ(*sizes, (EnvironmentSizes{8, 4}));
    const EnvironmentSizes forIbl = sizesForEnvironmentGraph(*sizes, frame, ibl);
    EXPECT_EQ(forIbl, (EnvironmentSizes{8, 32})) << "6 roughness levels need a 32^2 base";
    EXPECT_EQ(sizesForEnvironmentGraph(*sizes, raster, ibl), *sizes) << "raster.json's prefiltered sizes both";
    GraphDesc resized = ibl;
    resizeEnvironmentGraph(resized, forIbl);
    EXPECT_NO_THROW((void)compile(resized, CompileOptions{}));
    resized = ibl;
    resizeEnvironmentGraph(resized, *sizes);
    EXPECT_THROW((void)compile(resized, CompileOptions{}), GraphError) << "the case this guards against";
}

TEST_F(ShippedGraphs, ResizedGraphsCompileAndAgreeOnTheProducts) {
    for (const EnvironmentSizes sizes : {EnvironmentSizes{1, 32}, EnvironmentSizes{8, 32}, EnvironmentSizes{128, 64},
                                         EnvironmentSizes{512, 256}}) {
        SCOPED_TRACE(::testing::Message() << "environment " << sizes.environment << ", prefiltered "
                                          << sizes.prefiltered);
        GraphDesc frame = raster, environment = ibl;
        resizeEnvironmentGraph(frame, sizes);
        resizeEnvironmentGraph(environment, sizes);
        CompileOptions co;
        co.features = {{"environment_file", true}, {"sample_cubemap", true}};
        const Plan framePlan = compile(frame, co);
        const Plan environmentPlan = compile(environment, CompileOptions{});
        for (const char* product : {"environment", "prefiltered"}) {
            EXPECT_EQ(extentOf(framePlan, frame, product), product == std::string("environment") ? sizes.environment
                                                                                                 : sizes.prefiltered);
            EXPECT_EQ(extentOf(framePlan, frame, product), extentOf(environmentPlan, environment, product));
        }
        // One mip pass per level below the base, each writing the level under its source.
        uint32_t mipPasses = 0;
        for (const PlannedPass& p : environmentPlan.passes())
            if (p.type == "CubemapMipPass") ++mipPasses;
        EXPECT_EQ(mipPasses, uint32_t(std::bit_width(sizes.environment)) - 1);
    }
}

}  // namespace
}  // namespace skygraph
