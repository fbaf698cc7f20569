#version 450
#extension GL_GOOGLE_include_directive : require
// PrefilterPass, one mip: the split-sum prefiltered radiance (Karis 2013) for perceptual
// roughness r (alpha = r^2) with n = v = r:
//   P(n) = integral of L(l) D(h) (n.l) dl / integral of D(h) (n.l) dl,  h = normalize(n + l).
// GGX-distributed Hammersley half vectors, weighted by n.l; each sample reads the source mip
// whose texel solid angle matches the sample's (pdf(l) = D(h) / 4 when n = v). Roughness 0
// is the environment itself, read at the level of the written size.
#include "common/ibl.glsl"
#include "common/brdf.glsl"

#ifndef OUT_FORMAT
#define OUT_FORMAT rgba16f
#endif

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0) uniform samplerCube environment;  // with its mip chain
layout(set = 0, binding = 1, OUT_FORMAT) uniform writeonly image2DArray prefiltered;

layout(push_constant) uniform Params {
    int faceSize;            // of the mip written
    int samples;
    float environmentSize;   // face size of the environment's mip 0
    float roughness;         // perceptual
    float lodBias;
} params;

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    if (texel.x >= params.faceSize || texel.y >= params.faceSize) return;
    vec2 st = (vec2(texel.xy) + 0.5) / float(params.faceSize);
    vec3 n = normalize(cubeToDirection(texel.z, st));
    if (params.roughness <= 0.0) {
        float lod = max(log2(params.environmentSize / float(params.faceSize)), 0.0);
        imageStore(prefiltered, texel, vec4(textureLod(environment, n, lod).rgb, 1.0));
        return;
    }
    float alpha = params.roughness * params.roughness;
    mat3 frame = basisAround(n);
    uint count = uint(params.samples);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (uint i = 0u; i < count; ++i) {
        vec3 h = sampleGgxHalfVector(hammersley(i, count), alpha);
        float nl = 2.0 * h.z * h.z - 1.0;  // l = reflect(-n, h) in the frame around n
        if (nl <= 0.0) continue;
        vec3 l = frame * vec3(2.0 * h.z * h.xy, nl);
        float pdf = ggxD(h.z, alpha) * 0.25;
        float lod = sourceLod(pdf, float(count), params.environmentSize) + params.lodBias;
        sum += textureLod(environment, l, lod).rgb * nl;
        weight += nl;
    }
    imageStore(prefiltered, texel, vec4(sum / max(weight, 1e-8), 1.0));
}
