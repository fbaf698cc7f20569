#version 450
#extension GL_GOOGLE_include_directive : require
// BrdfLutPass: the split-sum BRDF table (Karis 2013) with the height-correlated Smith
// visibility of shaders/common/brdf.glsl. Texel (i, j) holds, for n.v = (i + 0.5) / width
// and perceptual roughness (j + 0.5) / height (alpha = roughness^2),
//   A = integral of (1 - Fc) f/F0-part,  B = integral of Fc,  Fc = (1 - v.h)^5,
// so that the specular response to a white furnace is F0 * A + B.
#include "common/ibl.glsl"
#include "common/brdf.glsl"

#ifndef OUT_FORMAT
#define OUT_FORMAT rg16f
#endif

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0, OUT_FORMAT) uniform writeonly image2D lut;

layout(push_constant) uniform Params {
    ivec2 size;
    int samples;
} params;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (texel.x >= params.size.x || texel.y >= params.size.y) return;
    float nv = (float(texel.x) + 0.5) / float(params.size.x);
    float roughness = (float(texel.y) + 0.5) / float(params.size.y);
    float alpha = roughness * roughness;
    vec3 v = vec3(sqrt(1.0 - nv * nv), 0.0, nv);
    uint count = uint(params.samples);
    vec2 sum = vec2(0.0);
    for (uint i = 0u; i < count; ++i) {
        vec3 h = sampleGgxHalfVector(hammersley(i, count), alpha);
        float vh = dot(v, h);
        vec3 l = 2.0 * vh * h - v;
        if (l.z <= 0.0 || vh <= 0.0) continue;
        // Estimator of f * (n.l) / pdf with pdf(l) = D (n.h) / (4 v.h), f = D F V.
        float g = smithVisibility(nv, l.z, alpha) * 4.0 * l.z * vh / h.z;
        float fc = pow(1.0 - vh, 5.0);
        sum += vec2((1.0 - fc) * g, fc * g);
    }
    imageStore(lut, texel, vec4(sum / float(count), 0.0, 0.0));
}
