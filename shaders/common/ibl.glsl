// Image-based lighting helpers for the environment pipeline (shaders/passes/ibl/*.comp),
// mirroring include/skygraph/ibl_math.hpp and the cube mapping of shading_math.hpp.
#ifndef SKYGRAPH_IBL_GLSL
#define SKYGRAPH_IBL_GLSL

// Not common/environment.glsl: its equirectLod uses derivatives, which compute shaders lack.
const float IBL_PI = 3.14159265358979323846;

// u = 0.5 + atan2(x, -z) / 2pi, v = acos(y) / pi, as environment.glsl's directionToEquirect.
vec2 equirectCoordinate(vec3 d) {
    return vec2(0.5 + atan(d.x, -d.z) / (2.0 * IBL_PI), acos(clamp(d.y, -1.0, 1.0)) / IBL_PI);
}

// The direction through (s, t) in [0,1]^2 of cube face `face` (+X,-X,+Y,-Y,+Z,-Z = 0..5):
// the inverse of Vulkan's cube map face selection. Not normalized.
vec3 cubeToDirection(int face, vec2 st) {
    float sc = 2.0 * st.x - 1.0, tc = 2.0 * st.y - 1.0;
    if (face == 0) return vec3(1.0, -tc, -sc);
    if (face == 1) return vec3(-1.0, -tc, sc);
    if (face == 2) return vec3(sc, 1.0, tc);
    if (face == 3) return vec3(sc, -1.0, -tc);
    if (face == 4) return vec3(sc, -tc, 1.0);
    return vec3(-sc, -tc, -1.0);
}

// Point i of an n-point Hammersley set in [0,1)^2.
vec2 hammersley(uint i, uint n) {
    return vec2((float(i) + 0.5) / float(n), float(bitfieldReverse(i)) * 2.3283064365386963e-10);
}

// An orthonormal basis around unit vector n (Frisvad / Duff et al. 2017).
mat3 basisAround(vec3 n) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float b = n.x * n.y * a;
    vec3 t = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    vec3 u = vec3(b, s + n.y * n.y * a, -n.y);
    return mat3(t, u, n);
}

// GGX half vector around +Z for alpha = roughness^2; pdf(h) = D(h) (n.h).
vec3 sampleGgxHalfVector(vec2 xi, float alpha) {
    float a2 = alpha * alpha;
    float phi = 2.0 * IBL_PI * xi.x;
    float cosTheta = sqrt((1.0 - xi.y) / (1.0 + (a2 - 1.0) * xi.y));
    float sinTheta = sqrt(max(1.0 - cosTheta * cosTheta, 0.0));
    return vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}

// Cosine-weighted direction around +Z; pdf(l) = (n.l) / pi.
vec3 sampleCosine(vec2 xi) {
    float phi = 2.0 * IBL_PI * xi.x;
    float r = sqrt(xi.y);
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(1.0 - xi.y, 0.0)));
}

// Filtered importance sampling (Krivanek & Colbert, GPU Gems 3 ch. 20): the source mip whose
// texel solid angle matches the solid angle one of `samples` samples of density `pdf` covers.
float sourceLod(float pdf, float samples, float faceSize) {
    float omegaSample = 1.0 / (samples * max(pdf, 1e-8));
    float omegaTexel = 4.0 * IBL_PI / (6.0 * faceSize * faceSize);
    return max(0.5 * log2(omegaSample / omegaTexel), 0.0);
}

#endif
