// The CPU reference math: properties that must hold exactly, and the extremes the GPU
// versions are later held to.
#include <skygraph/shading_math.hpp>

#include <gtest/gtest.h>

#include <limits>

namespace skygraph::math {
namespace {

const double kInf = std::numeric_limits<double>::infinity();
const double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(Tonemap, EveryOperatorIsFiniteAndInRangeForHostileInputs) {
    const double inputs[] = {kInf, -kInf, kNaN, -1e4, -0.0, 0.0, 1e-30, 0.18, 1.0, 65504.0, 65520.0, 1e38};
    const double evs[] = {-40.0, -8.0, 0.0, 8.0, 40.0};
    for (auto op : {ToneOperator::AcesNarkowicz, ToneOperator::AcesHill, ToneOperator::KhronosPbrNeutral,
                    ToneOperator::Passthrough})
        for (double ev : evs)
            for (double r : inputs)
                for (double g : {0.0, r, kNaN})
                    for (int precision = 0; precision < 2; ++precision) {
                        Vec3<double> out;
                        if (precision == 0) {
                            out = tonemap(Vec3<double>(r, g, 0.5), ev, op);
                        } else {
                            const auto f = tonemap(Vec3<float>(float(r), float(g), 0.5f), float(ev), op);
                            out = Vec3<double>(f);
                        }
                        for (int i = 0; i < 3; ++i) {
                            ASSERT_TRUE(std::isfinite(out[i])) << "op " << int(op) << " ev " << ev << " in " << r;
                            ASSERT_GE(out[i], 0.0);
                            ASSERT_LE(out[i], 1.0);
                        }
                    }
}

TEST(Tonemap, NarkowiczMatchesTheSeedConstants) {
    // f(x) = x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), evaluated by hand at x = 1.
    EXPECT_NEAR(acesNarkowicz(1.0), 2.54 / 3.16, 1e-15);
    EXPECT_EQ(acesNarkowicz(0.0), 0.0);
    EXPECT_EQ(acesNarkowicz(1e4), 1.0) << "saturates: the curve's limit 2.51/2.43 is clamped";
}

TEST(Tonemap, ExposureIsTwoToTheEv) {
    const auto a = tonemap(Vec3<double>(0.25), 1.0, ToneOperator::AcesNarkowicz);
    const auto b = tonemap(Vec3<double>(0.5), 0.0, ToneOperator::AcesNarkowicz);
    EXPECT_DOUBLE_EQ(a.r, b.r);
}

TEST(Tonemap, NeutralLeavesMidtonesAlone) {
    // Below the compression start, Khronos PBR Neutral only subtracts the toe offset.
    const auto c = khronosPbrNeutral(Vec3<double>(0.5, 0.4, 0.3));
    EXPECT_NEAR(c.r, 0.5 - 0.04, 1e-12);
    EXPECT_NEAR(c.b, 0.3 - 0.04, 1e-12);
}

TEST(Srgb, EncodeMatchesTheStandardAndRoundTrips) {
    EXPECT_DOUBLE_EQ(srgbEncode(0.0), 0.0);
    EXPECT_DOUBLE_EQ(srgbEncode(1.0), 1.0);
    EXPECT_NEAR(srgbEncode(0.0031308), 0.0404500, 1e-6);
    EXPECT_NEAR(srgbEncode(0.18) * 255.0, 117.6458, 1e-3);
    for (double x = 0; x <= 1.0; x += 1.0 / 1024) EXPECT_NEAR(srgbDecode(srgbEncode(x)), x, 1e-12);
}

TEST(Cube, FaceSelectionFollowsTheVulkanTable) {
    // Centres of the six faces, in layer order.
    const Vec3<double> axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int f = 0; f < 6; ++f) {
        const auto c = directionToCube(axes[f]);
        EXPECT_EQ(c.face, f);
        EXPECT_DOUBLE_EQ(c.st.x, 0.5);
        EXPECT_DOUBLE_EQ(c.st.y, 0.5);
    }
    // +X face: s grows towards -Z, t grows towards -Y (spec: sc = -rz, tc = -ry).
    const auto c = directionToCube(Vec3<double>(1, -0.5, -0.5));
    EXPECT_EQ(c.face, 0);
    EXPECT_DOUBLE_EQ(c.st.x, 0.75);
    EXPECT_DOUBLE_EQ(c.st.y, 0.75);
    // +Y face: tc = +rz.
    EXPECT_DOUBLE_EQ(directionToCube(Vec3<double>(0, 1, 0.5)).st.y, 0.75);
}

TEST(Cube, RoundTripsAcrossEveryFaceIncludingEdgesAndCorners) {
    for (int f = 0; f < 6; ++f)
        for (double s : {0.0, 0.001, 0.25, 0.5, 0.999, 1.0})
            for (double t : {0.0, 0.37, 0.5, 1.0}) {
                const auto d = cubeToDirection(f, Vec2<double>(s, t));
                const auto back = directionToCube(d);
                const auto again = cubeToDirection(back.face, back.st);
                EXPECT_NEAR(glm::length(glm::normalize(d) - glm::normalize(again)), 0.0, 1e-15);
            }
}

TEST(Equirect, RoundTripsIncludingSeamAndPoles) {
    for (double u : {0.0, 1e-9, 0.25, 0.5, 0.75, 1.0 - 1e-9})
        for (double v : {1e-9, 0.1, 0.5, 0.9, 1.0 - 1e-9}) {
            const auto d = equirectToDirection(Vec2<double>(u, v));
            EXPECT_NEAR(glm::length(d), 1.0, 1e-15);
            const auto uv = directionToEquirect(d);
            EXPECT_NEAR(uv.y, v, 1e-7);
            EXPECT_NEAR(std::fmod(uv.x - u + 1.5, 1.0) - 0.5, 0.0, 1e-7);
        }
    // -Z is the centre of the map, +Y the top row.
    EXPECT_DOUBLE_EQ(directionToEquirect(Vec3<double>(0, 0, -1)).x, 0.5);
    EXPECT_DOUBLE_EQ(directionToEquirect(Vec3<double>(0, 1, 0)).y, 0.0);
}

TEST(Camera, ProjectionIsReverseZWithAnInfiniteFarPlane) {
    const auto p = reverseZInfiniteProjection(60.0, 1.5, 0.1);
    auto depth = [&](double z) {
        const auto c = p * glm::dvec4(0, 0, z, 1);
        return c.z / c.w;
    };
    EXPECT_DOUBLE_EQ(depth(-0.1), 1.0);
    EXPECT_NEAR(depth(-1e12), 0.0, 1e-12);
    // +Y in view space lands at negative NDC y (Vulkan's +Y is down).
    const auto c = p * glm::dvec4(0, 1, -2, 1);
    EXPECT_LT(c.y / c.w, 0.0);
}

TEST(Camera, RayDirectionsMatchProjectedPoints) {
    const auto r = cameraRotation(30.0, -20.0, 10.0);
    const glm::dvec3 pos(3, 4, 5);
    const auto proj = reverseZInfiniteProjection(50.0, 16.0 / 9.0, 0.01);
    const auto view = viewMatrix(pos, r);
    for (double x : {-0.9, 0.0, 0.7})
        for (double y : {-0.8, 0.3}) {
            const auto dir = glm::normalize(viewRayFromNdc(glm::dvec2(x, y), r, 50.0, 16.0 / 9.0));
            const auto clip = proj * view * glm::dvec4(pos + dir * 10.0, 1.0);
            EXPECT_NEAR(clip.x / clip.w, x, 1e-12);
            EXPECT_NEAR(clip.y / clip.w, y, 1e-12);
        }
}

TEST(Camera, RotationOnlyRaysStayExactFarFromTheOriginWhereTheSeedsMethodFails) {
    // Camera at 1e7 with a 1e-5 near plane, in float as a shader would compute it.
    const float fov = 60.0f, aspect = 1.0f, nearPlane = 1e-5f;
    const double pixelAngle = radians(60.0) / 1080.0;
    const auto rf = cameraRotation(20.0f, 10.0f, 0.0f);
    const auto rd = cameraRotation(20.0, 10.0, 0.0);
    const glm::vec3 pos(1e7f, 0.0f, 1e7f);
    const auto invViewProj = glm::inverse(reverseZInfiniteProjection(fov, aspect, nearPlane) * viewMatrix(pos, rf));
    // Angle via atan2(|a x b|, a . b): acos near 1 would drown the answer in rounding.
    auto angle = [](const glm::dvec3& a, const glm::dvec3& b) {
        return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
    };
    double worstOurs = 0, worstSeed = 0;
    for (float x : {-0.9f, 0.1f, 0.8f})
        for (float y : {-0.7f, 0.5f}) {
            const auto exact = glm::normalize(viewRayFromNdc(glm::dvec2(x, y), rd, 60.0, 1.0));
            const auto ours = glm::dvec3(glm::normalize(viewRayFromNdc(glm::vec2(x, y), rf, fov, aspect)));
            const auto seed = glm::dvec3(glm::normalize(seedViewRay(glm::vec2(x, y), invViewProj, pos)));
            worstOurs = std::max(worstOurs, angle(exact, ours) / pixelAngle);
            const double seedAngle = angle(exact, seed);
            worstSeed = std::max(worstSeed, std::isfinite(seedAngle) ? seedAngle / pixelAngle : 1e9);
        }
    EXPECT_LT(worstOurs, 1e-3) << "error in pixels at 1080p";
    EXPECT_GT(worstSeed, 100.0) << "the near-point method should be visibly wrong here";
    RecordProperty("seed_error_px", std::to_string(worstSeed));
}

TEST(ProceduralSky, IsFinitePositiveAndContinuousAcrossTheHorizon) {
    for (double y = -1.0; y <= 1.0; y += 0.01) {
        const auto c = proceduralSky(glm::dvec3(0.3, y, -0.7));
        for (int i = 0; i < 3; ++i) {
            EXPECT_TRUE(std::isfinite(c[i]));
            EXPECT_GT(c[i], 0.0);
        }
    }
    const auto above = proceduralSky(glm::dvec3(1, 1e-9, 0)), below = proceduralSky(glm::dvec3(1, -1e-9, 0));
    EXPECT_NEAR(glm::length(above - below * 2.0), 0.0, 1e-4) << "the ground fades in from half the horizon";
}

}  // namespace
}  // namespace skygraph::math
