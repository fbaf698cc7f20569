// Reference math of the environment pipeline in double precision: what the compute passes
// of graphs/ibl.json (shaders/passes/ibl/*.comp, shaders/common/ibl.glsl) approximate, for
// tests and benchmarks to measure them against. Radiance is any callable
// `Vec3<double>(const Vec3<double>& unitDirection)`. Conventions: docs/environment.md.
#pragma once

#include <skygraph/shading_math.hpp>

#include <cstdint>

namespace skygraph::math::ibl {

using Dir = Vec3<double>;

/// Point i of an n-point Hammersley set in [0,1)^2 (x at the cell centre, y the base-2
/// radical inverse), as the shaders use it.
inline Vec2<double> hammersley(uint32_t i, uint32_t n) {
    uint32_t bits = i;
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return {(double(i) + 0.5) / double(n), double(bits) * 2.3283064365386963e-10};
}

/// Columns t, b, n of an orthonormal basis around unit vector n.
inline Mat3<double> basisAround(const Dir& n) {
    const double s = n.z >= 0 ? 1.0 : -1.0;
    const double a = -1.0 / (s + n.z);
    const double b = n.x * n.y * a;
    return Mat3<double>(Dir(1.0 + s * n.x * n.x * a, s * b, -s * n.x), Dir(b, s + n.y * n.y * a, -n.y), n);
}

/// GGX normal distribution D(n.h) for alpha = roughness^2.
inline double ggxD(double nh, double alpha) {
    const double a2 = alpha * alpha;
    const double d = nh * nh * (a2 - 1.0) + 1.0;
    return a2 / (kPi<double> * d * d);
}

/// Height-correlated Smith visibility V = G / (4 n.l n.v), as shaders/common/brdf.glsl.
inline double smithVisibility(double nv, double nl, double alpha) {
    const double a2 = alpha * alpha;
    const double v = nl * std::sqrt(nv * nv * (1.0 - a2) + a2);
    const double l = nv * std::sqrt(nl * nl * (1.0 - a2) + a2);
    return 0.5 / (v + l);
}

/// GGX-distributed half vector around +Z (pdf D(h) n.h) from a point of [0,1)^2.
inline Dir sampleGgxHalfVector(const Vec2<double>& xi, double alpha) {
    const double a2 = alpha * alpha;
    const double phi = 2.0 * kPi<double> * xi.x;
    const double cosTheta = std::sqrt((1.0 - xi.y) / (1.0 + (a2 - 1.0) * xi.y));
    const double sinTheta = std::sqrt(std::max(1.0 - cosTheta * cosTheta, 0.0));
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

/// Cosine-distributed direction around +Z (pdf n.l / pi).
inline Dir sampleCosine(const Vec2<double>& xi) {
    const double phi = 2.0 * kPi<double> * xi.x;
    const double r = std::sqrt(xi.y);
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(1.0 - xi.y, 0.0))};
}

/// Mean radiance over texel (x, y) of face `face` of a size x size cube, as the mean of
/// n x n point values on an even sub-texel grid in (s, t): the quantity the supersampled
/// equirect -> cube pass estimates (n -> infinity is the exact (s, t)-area mean).
template <typename Radiance>
Dir cubeTexelMean(Radiance&& radiance, int face, int x, int y, int size, int n) {
    Dir sum(0.0);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec2<double> st((x + (i + 0.5) / n) / size, (y + (j + 0.5) / n) / size);
            sum += radiance(glm::normalize(cubeToDirection(face, st)));
        }
    return sum / double(n * n);
}

/// E(n) / pi = (1/pi) * integral of L(l) max(n.l, 0) dl: the radiance a white Lambertian
/// surface of normal n reflects (what the irradiance cube stores). Quasi-Monte Carlo with
/// `samples` cosine-distributed points.
template <typename Radiance>
Dir irradianceOverPi(Radiance&& radiance, const Dir& n, uint32_t samples = 1u << 16) {
    const Mat3<double> frame = basisAround(n);
    Dir sum(0.0);
    for (uint32_t i = 0; i < samples; ++i) sum += radiance(glm::normalize(frame * sampleCosine(hammersley(i, samples))));
    return sum / double(samples);
}

/// The split-sum prefiltered radiance for perceptual roughness r (alpha = r^2), n = v:
///   P(n) = integral of L(l) D(h) (n.l) dl / integral of D(h) (n.l) dl,  h = normalize(n + l),
/// by quasi-Monte Carlo over GGX half vectors (pdf(l) = D / 4, so the weight is n.l).
/// Roughness 0 is L(n).
template <typename Radiance>
Dir prefilteredRadiance(Radiance&& radiance, const Dir& n, double roughness, uint32_t samples = 1u << 16) {
    if (roughness <= 0.0) return radiance(n);
    const double alpha = roughness * roughness;
    const Mat3<double> frame = basisAround(n);
    Dir sum(0.0);
    double weight = 0.0;
    for (uint32_t i = 0; i < samples; ++i) {
        const Dir h = sampleGgxHalfVector(hammersley(i, samples), alpha);
        const double nl = 2.0 * h.z * h.z - 1.0;
        if (nl <= 0.0) continue;
        sum += radiance(glm::normalize(frame * Dir(2.0 * h.z * h.x, 2.0 * h.z * h.y, nl))) * nl;
        weight += nl;
    }
    return sum / weight;
}

/// The split-sum BRDF table entry (A, B) for n.v and perceptual roughness r: the specular
/// response to uniform white light is F0 * A + B (Schlick Fresnel, GGX, height-correlated
/// Smith visibility).
inline Vec2<double> brdfIntegral(double nv, double roughness, uint32_t samples = 1u << 16) {
    const double alpha = roughness * roughness;
    const Dir v(std::sqrt(1.0 - nv * nv), 0.0, nv);
    Vec2<double> sum(0.0);
    for (uint32_t i = 0; i < samples; ++i) {
        const Dir h = sampleGgxHalfVector(hammersley(i, samples), alpha);
        const double vh = glm::dot(v, h);
        const Dir l = 2.0 * vh * h - v;
        if (l.z <= 0.0 || vh <= 0.0) continue;
        const double g = smithVisibility(nv, l.z, alpha) * 4.0 * l.z * vh / h.z;
        const double fc = std::pow(1.0 - vh, 5.0);
        sum += Vec2<double>((1.0 - fc) * g, fc * g);
    }
    return sum / double(samples);
}

}  // namespace skygraph::math::ibl
