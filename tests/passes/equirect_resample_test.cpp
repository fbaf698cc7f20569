// resampleEquirect, which lets `skygraph view` bake a file of another size beside its frames:
// shrinking keeps the map's integral (a sun's power), growing interpolates and wraps around
// in longitude.
#include "app/environment_bake.hpp"
#include "app/equirect_resample.hpp"

#include <skygraph/shading_math.hpp>

#include <gtest/gtest.h>

#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <numeric>
#include <random>

#include <unistd.h>

namespace skygraph::test {
namespace {

HdrImage randomMap(uint32_t w, uint32_t h, uint32_t seed) {
    std::mt19937 rng(seed);
    std::exponential_distribution<float> radiance(0.5f);
    HdrImage m{w, h, std::vector<float>(size_t(w) * h * 4)};
    for (size_t i = 0; i < m.rgba.size(); ++i) m.rgba[i] = i % 4 == 3 ? 1.0f : radiance(rng);
    return m;
}

double meanOf(const HdrImage& m, int channel) {
    double sum = 0.0;
    for (size_t i = size_t(channel); i < m.rgba.size(); i += 4) sum += m.rgba[i];
    return sum / (double(m.width) * m.height);
}

TEST(EquirectResample, ShrinkingKeepsTheMeanAndASunsPower) {
    // 1000 x 500 to 640 x 320: footprints of 1.5625 texels, partly covered ones included.
    HdrImage map = randomMap(1000, 500, 5);
    map.rgba[(size_t(123) * 1000 + 777) * 4] = 50000.0f;  // a one-texel sun
    const HdrImage small = app::resampleEquirect(map, 640, 320);
    ASSERT_EQ(small.rgba.size(), size_t(640) * 320 * 4);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(meanOf(small, c), meanOf(map, c), 1e-5 * meanOf(map, c)) << c;
    EXPECT_NEAR(meanOf(small, 3), 1.0, 1e-6) << "alpha stays 1";
    // The sun spreads over the texels its footprint touches, with its power intact.
    double sun = 0.0;
    for (uint32_t y = 75; y < 82; ++y)
        for (uint32_t x = 494; x < 501; ++x) sun += small.pixel(x, y)[0] - meanOf(map, 0);
    EXPECT_NEAR(sun * (1000.0 * 500.0) / (640.0 * 320.0), 50000.0, 50000.0 * 0.01);
}

TEST(EquirectResample, GrowingInterpolatesAndWrapsInLongitudeOnly) {
    HdrImage map{2, 2, std::vector<float>(16, 1.0f)};
    // Columns 0 and 1 hold 0 and 4 in red; rows are equal.
    for (uint32_t y = 0; y < 2; ++y) {
        map.rgba[(size_t(y) * 2 + 0) * 4] = 0.0f;
        map.rgba[(size_t(y) * 2 + 1) * 4] = 4.0f;
    }
    const HdrImage big = app::resampleEquirect(map, 8, 4);
    // Output texel x has its centre at input (x + 0.5) / 4 - 0.5: x = 0 at -0.375, between
    // column 1 (wrapped around, at -1: weight 0.375) and column 0; x = 2 at 0.125; x = 7 at
    // 1.375, between column 1 and column 0 wrapped around (at 2: weight 0.375).
    EXPECT_FLOAT_EQ(big.pixel(0, 0)[0], 4.0f * 0.375f);
    EXPECT_FLOAT_EQ(big.pixel(2, 0)[0], 4.0f * 0.125f);
    EXPECT_FLOAT_EQ(big.pixel(7, 0)[0], 4.0f * 0.625f) << "the last column blends back towards column 0";
    for (uint32_t y = 0; y < 4; ++y) EXPECT_FLOAT_EQ(big.pixel(3, y)[0], big.pixel(3, 0)[0]) << "clamped at the poles";
}

TEST(EquirectResample, TheSameSizeIsACopy) {
    const HdrImage map = randomMap(64, 32, 9);
    EXPECT_EQ(app::resampleEquirect(map, 64, 32).rgba, map.rgba);
}

}  // namespace
}  // namespace skygraph::test

// loadEnvironmentImage, the one way the application reads an environment file: values the
// half-float products cannot hold are clamped, and NaN or infinity is refused.
namespace skygraph::test {
namespace {

TEST(EnvironmentImage, ValuesPastTheLargestHalfAreClampedAndNonFiniteOnesRefused) {
    const auto base = std::filesystem::temp_directory_path() / ("skygraph-environment-" + std::to_string(::getpid()));
    const auto hdr = base.string() + ".hdr", exr = base.string() + ".exr";
    HdrImage sky{4, 2, std::vector<float>(4 * 2 * 4, 1.0f)};
    sky.rgba[0] = 1.0e30f;  // a half float's infinity
    saveHdrImage(hdr, sky);
    const HdrImage clamped = app::loadEnvironmentImage(hdr);
    EXPECT_EQ(clamped.rgba[0], math::kLargestHalf);
    EXPECT_EQ(clamped.rgba[4], 1.0f) << "the next pixel as it was";
    sky.rgba[0] = std::numeric_limits<float>::infinity();
    saveExr(exr, sky);
    try {
        (void)app::loadEnvironmentImage(exr);
        ADD_FAILURE() << "an infinite value was taken";
    } catch (const ImageError& e) {
        EXPECT_EQ(e.file(), exr);
        EXPECT_NE(std::string(e.what()).find("1 pixel values are NaN or infinite"), std::string::npos) << e.what();
    }
    std::filesystem::remove(hdr);
    std::filesystem::remove(exr);
}

// An EXR can hold negative colours (a Radiance file cannot); radiance is never negative.
TEST(EnvironmentImage, NegativeColourValuesAreClampedToZero) {
    const auto exr = std::filesystem::temp_directory_path() / ("skygraph-negative-" + std::to_string(::getpid()) + ".exr");
    HdrImage sky{4, 2, std::vector<float>(4 * 2 * 4, 1.0f)};
    sky.rgba[0] = -0.25f;
    sky.rgba[6] = -60000.0f;
    saveExr(exr, sky);
    const HdrImage loaded = app::loadEnvironmentImage(exr);
    EXPECT_EQ(loaded.rgba[0], 0.0f);
    EXPECT_EQ(loaded.rgba[6], 0.0f);
    for (size_t i : {1u, 2u, 3u, 4u, 5u, 7u}) EXPECT_EQ(loaded.rgba[i], 1.0f) << "value " << i << " as it was";
    std::filesystem::remove(exr);
}

// Every command that takes a sky (cubemap, render, view, sky sequences) loads it here.
TEST(EnvironmentImage, OneThatIsNot2To1IsWarnedOf) {
    const auto exr = std::filesystem::temp_directory_path() / ("skygraph-square-" + std::to_string(::getpid()) + ".exr");
    const auto sink = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(8);
    const auto previous = spdlog::default_logger();
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("environment_test", sink));
    for (const uint32_t width : {4u, 3u}) {
        saveExr(exr, HdrImage{width, 2, std::vector<float>(size_t(width) * 2 * 4, 1.0f)});
        (void)app::loadEnvironmentImage(exr);
    }
    spdlog::set_default_logger(previous);
    const std::vector<std::string> lines = sink->last_formatted();
    ASSERT_EQ(lines.size(), 1u) << "the 4x2 image is 2:1";
    EXPECT_NE(lines[0].find("is 3x2, not 2:1; it is read as an equirect map all the same"), std::string::npos) << lines[0];
    std::filesystem::remove(exr);
}

}  // namespace
}  // namespace skygraph::test
