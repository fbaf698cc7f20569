// The math of the built-in passes, on the CPU, templated on the scalar type: `double` is the
// reference that GPU images are tested against; `float` mirrors the GLSL in shaders/common/
// line for line. Conventions (docs/conventions.md):
//   - world: right-handed, +Y up; a camera with yaw = pitch = roll = 0 looks down -Z;
//     yaw turns left (about +Y), pitch looks up (about +X), roll turns about the view axis;
//   - clip: Vulkan, NDC +Y down (the projection flips Y, so viewports stay positive);
//   - depth: reverse-Z with an infinite far plane: 1 at the near plane, 0 at infinity.
// Every function is pure: it returns a value computed from its arguments, keeps no state and
// throws nothing.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace skygraph::math {

template <typename T>
using Vec2 = glm::vec<2, T, glm::defaultp>;
template <typename T>
using Vec3 = glm::vec<3, T, glm::defaultp>;
template <typename T>
using Mat3 = glm::mat<3, 3, T, glm::defaultp>;
template <typename T>
using Mat4 = glm::mat<4, 4, T, glm::defaultp>;

template <typename T>
constexpr T kPi = std::numbers::pi_v<T>;

template <typename T>
T radians(T degrees) {
    return degrees * (kPi<T> / T(180));
}

// ---- camera ------------------------------------------------------------------------------

/// Camera-to-world rotation from yaw, pitch and roll in degrees (R = Ry(yaw) Rx(pitch) Rz(roll)).
template <typename T>
Mat3<T> cameraRotation(T yawDeg, T pitchDeg, T rollDeg) {
    const T y = radians(yawDeg), p = radians(pitchDeg), r = radians(rollDeg);
    const Mat3<T> ry{std::cos(y), 0, -std::sin(y), 0, 1, 0, std::sin(y), 0, std::cos(y)};
    const Mat3<T> rx{1, 0, 0, 0, std::cos(p), std::sin(p), 0, -std::sin(p), std::cos(p)};
    const Mat3<T> rz{std::cos(r), std::sin(r), 0, -std::sin(r), std::cos(r), 0, 0, 0, 1};
    return ry * rx * rz;
}

/// Reverse-Z, infinite far plane, Vulkan clip space with +Y down.
template <typename T>
Mat4<T> reverseZInfiniteProjection(T fovYDeg, T aspect, T nearPlane) {
    const T f = T(1) / std::tan(radians(fovYDeg) / T(2));
    Mat4<T> p(T(0));
    p[0][0] = f / aspect;
    p[1][1] = -f;
    p[2][3] = T(-1);  // w = -z_view
    p[3][2] = nearPlane;  // z = near, so depth = near / -z_view
    return p;
}

/// View matrix (world -> view) for a camera at `position` with rotation `r` (camera -> world).
template <typename T>
Mat4<T> viewMatrix(const Vec3<T>& position, const Mat3<T>& r) {
    const Mat3<T> rt = glm::transpose(r);
    Mat4<T> v(rt);
    v[3] = glm::vec<4, T, glm::defaultp>(-(rt * position), T(1));
    return v;
}

/// Un-normalized world direction through NDC point (x, y), from the rotation alone: exact at
/// any camera distance, because the camera position never enters (the skybox's method).
template <typename T>
Vec3<T> viewRayFromNdc(const Vec2<T>& ndc, const Mat3<T>& cameraToWorld, T fovYDeg, T aspect) {
    const T tanHalf = std::tan(radians(fovYDeg) / T(2));
    return cameraToWorld * Vec3<T>(ndc.x * aspect * tanHalf, -ndc.y * tanHalf, T(-1));
}

/// NDC of a pixel centre.
template <typename T>
Vec2<T> pixelToNdc(T px, T py, T width, T height) {
    return {(T(2) * (px + T(0.5)) / width) - T(1), (T(2) * (py + T(0.5)) / height) - T(1)};
}

/// The near-point method (unproject the near point, subtract the camera position), kept to
/// measure what it loses far from the origin. `invViewProj` maps clip to world.
template <typename T>
Vec3<T> seedViewRay(const Vec2<T>& ndc, const Mat4<T>& invViewProj, const Vec3<T>& position) {
    const auto w = invViewProj * glm::vec<4, T, glm::defaultp>(ndc.x, ndc.y, T(1), T(1));
    return Vec3<T>(w) / w.w - position;
}

/// Horizontal environment rotation from precomputed sine and cosine (about +Y).
template <typename T>
Vec3<T> rotateY(const Vec3<T>& d, T sinA, T cosA) {
    return {cosA * d.x + sinA * d.z, d.y, -sinA * d.x + cosA * d.z};
}

// ---- environment lookups --------------------------------------------------------------------

/// Equirect texture coordinate of a unit direction: u = 0.5 + atan2(x, -z) / 2π (u grows
/// turning right from -Z), v = acos(y) / π (0 at the zenith). Seam at u = 0/1 behind +Z.
template <typename T>
Vec2<T> directionToEquirect(const Vec3<T>& d) {
    const T u = T(0.5) + std::atan2(d.x, -d.z) / (T(2) * kPi<T>);
    const T v = std::acos(std::clamp(d.y, T(-1), T(1))) / kPi<T>;
    return {u, v};
}

/// Inverse of directionToEquirect.
template <typename T>
Vec3<T> equirectToDirection(const Vec2<T>& uv) {
    const T phi = (uv.x - T(0.5)) * T(2) * kPi<T>;
    const T theta = uv.y * kPi<T>;
    return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

/// Vulkan cube face selection (spec "Cube Map Face Selection and Transformations"): the
/// face index (+X,-X,+Y,-Y,+Z,-Z = 0..5) and the face's (s, t) in [0, 1].
template <typename T>
struct CubeCoord {
    int face = 0;
    Vec2<T> st;
};

template <typename T>
CubeCoord<T> directionToCube(const Vec3<T>& d) {
    const T ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    T sc, tc, ma;
    int face;
    if (ax >= ay && ax >= az) {
        face = d.x >= 0 ? 0 : 1;
        ma = ax;
        sc = d.x >= 0 ? -d.z : d.z;
        tc = -d.y;
    } else if (ay >= az) {
        face = d.y >= 0 ? 2 : 3;
        ma = ay;
        sc = d.x;
        tc = d.y >= 0 ? d.z : -d.z;
    } else {
        face = d.z >= 0 ? 4 : 5;
        ma = az;
        sc = d.z >= 0 ? d.x : -d.x;
        tc = -d.y;
    }
    return {face, {T(0.5) * (sc / ma + T(1)), T(0.5) * (tc / ma + T(1))}};
}

/// Inverse of directionToCube: the (un-normalized) direction through (s, t) of a face.
template <typename T>
Vec3<T> cubeToDirection(int face, const Vec2<T>& st) {
    const T sc = T(2) * st.x - T(1), tc = T(2) * st.y - T(1);
    switch (face) {
        case 0: return {T(1), -tc, -sc};
        case 1: return {T(-1), -tc, sc};
        case 2: return {sc, T(1), tc};
        case 3: return {sc, T(-1), -tc};
        case 4: return {sc, -tc, T(1)};
        default: return {-sc, -tc, T(-1)};
    }
}

/// The unit direction towards the procedural sky's sun (0.6 degrees in radius) unless a scene
/// says otherwise (SceneEnvironment::sunDirection).
template <typename T>
Vec3<T> proceduralSunDirection() {
    return glm::normalize(Vec3<T>(T(0.35), T(0.45), T(-0.82)));
}

/// The built-in procedural sky: a gradient from horizon to zenith, a darker ground, and a
/// sun disc with a soft glow towards the unit `sunDir`. Radiance in linear HDR units; smooth
/// except at the disc edge.
template <typename T>
Vec3<T> proceduralSky(const Vec3<T>& dirIn, const Vec3<T>& sunDir) {
    const Vec3<T> d = glm::normalize(dirIn);
    const Vec3<T> zenith(T(0.16), T(0.34), T(0.82)), horizon(T(0.75), T(0.85), T(1.0));
    const Vec3<T> ground(T(0.18), T(0.16), T(0.14));
    const T up = d.y;
    Vec3<T> sky = up >= 0 ? glm::mix(horizon, zenith, std::sqrt(up))
                          : glm::mix(horizon * T(0.5), ground, std::min(T(1), -up * T(4)));
    const T cosSun = glm::dot(d, sunDir);
    const T glow = std::pow(std::max(cosSun, T(0)), T(64)) * T(2);
    const T disc = cosSun > std::cos(radians(T(0.6))) ? T(400) : T(0);
    return sky + Vec3<T>(T(1), T(0.9), T(0.7)) * (glow + disc);
}

/// The procedural sky with its default sun.
template <typename T>
Vec3<T> proceduralSky(const Vec3<T>& dirIn) {
    return proceduralSky(dirIn, proceduralSunDirection<T>());
}

// ---- tone mapping ---------------------------------------------------------------------------

/// The largest finite half float: what an R16G16B16A16_SFLOAT image holds at most.
inline constexpr float kLargestHalf = 65504.0f;

/// Makes any input safe for the curves: NaN -> 0, negatives -> 0, everything above fp16 max
/// (including +inf) -> fp16 max. Done with comparisons because GLSL's clamp() does not remove
/// NaN. Every curve below saturates well before 65504, so nothing visible is lost.
template <typename T>
T sanitizeHdr(T x) {
    if (!(x == x)) return T(0);  // NaN
    if (!(x > T(0))) return T(0);
    return x < T(kLargestHalf) ? x : T(kLargestHalf);
}

/// Narkowicz 2015 ACES fit, his published constants (no 0.6 pre-exposure: docs/tradeoffs.md).
template <typename T>
T acesNarkowicz(T x) {
    const T a = T(2.51), b = T(0.03), c = T(2.43), d = T(0.59), e = T(0.14);
    return std::clamp((x * (a * x + b)) / (x * (c * x + d) + e), T(0), T(1));
}

/// Stephen Hill's fit of the ACES RRT+ODT (BakingLab), on linear sRGB input.
template <typename T>
Vec3<T> acesHill(const Vec3<T>& rgb) {
    const Mat3<T> input = glm::transpose(Mat3<T>(0.59719, 0.35458, 0.04823, 0.07600, 0.90834, 0.01566,
                                                 0.02840, 0.13383, 0.83777));
    const Mat3<T> output = glm::transpose(Mat3<T>(1.60475, -0.53108, -0.07367, -0.10208, 1.10813,
                                                  -0.00605, -0.00327, -0.07276, 1.07602));
    Vec3<T> v = input * rgb;
    v = (v * (v + T(0.0245786)) - T(0.000090537)) / (v * (T(0.983729) * v + T(0.4329510)) + T(0.238081));
    return glm::clamp(output * v, T(0), T(1));
}

/// Khronos PBR Neutral (2024 reference implementation).
template <typename T>
Vec3<T> khronosPbrNeutral(Vec3<T> c) {
    const T startCompression = T(0.8) - T(0.04), desaturation = T(0.15);
    const T x = std::min(c.r, std::min(c.g, c.b));
    const T offset = x < T(0.08) ? x - T(6.25) * x * x : T(0.04);
    c -= offset;
    const T peak = std::max(c.r, std::max(c.g, c.b));
    if (peak < startCompression) return c;
    const T d = T(1) - startCompression;
    const T newPeak = T(1) - d * d / (peak + d - startCompression);
    c *= newPeak / peak;
    const T g = T(1) - T(1) / (desaturation * (peak - newPeak) + T(1));
    return glm::mix(c, Vec3<T>(newPeak), g);
}

enum class ToneOperator { AcesNarkowicz, AcesHill, KhronosPbrNeutral, Passthrough };

/// The whole tonemapping pass on one pixel: sanitize, expose by 2^EV, curve. Passthrough
/// (debug views) skips exposure and the curve. Result in [0, 1], linear.
template <typename T>
Vec3<T> tonemap(Vec3<T> hdr, T exposureEv, ToneOperator op) {
    for (int i = 0; i < 3; ++i) hdr[i] = sanitizeHdr(hdr[i]);
    if (op == ToneOperator::Passthrough) return glm::clamp(hdr, T(0), T(1));
    const T exposure = std::exp2(std::clamp(exposureEv, T(-64), T(64)));
    for (int i = 0; i < 3; ++i) hdr[i] = sanitizeHdr(hdr[i] * exposure);
    switch (op) {
        case ToneOperator::AcesNarkowicz:
            return {acesNarkowicz(hdr.r), acesNarkowicz(hdr.g), acesNarkowicz(hdr.b)};
        case ToneOperator::AcesHill: return acesHill(hdr);
        case ToneOperator::KhronosPbrNeutral: return glm::clamp(khronosPbrNeutral(hdr), T(0), T(1));
        case ToneOperator::Passthrough: break;
    }
    return hdr;
}

/// The sRGB transfer function (IEC 61966-2-1), linear [0,1] -> encoded [0,1].
template <typename T>
T srgbEncode(T linear) {
    linear = std::clamp(linear, T(0), T(1));
    return linear <= T(0.0031308) ? linear * T(12.92) : T(1.055) * std::pow(linear, T(1) / T(2.4)) - T(0.055);
}

template <typename T>
T srgbDecode(T encoded) {
    encoded = std::clamp(encoded, T(0), T(1));
    return encoded <= T(0.04045) ? encoded / T(12.92) : std::pow((encoded + T(0.055)) / T(1.055), T(2.4));
}

}  // namespace skygraph::math
