#version 450
#extension GL_GOOGLE_include_directive : require
// IrradiancePass: a small cube of E(n) / pi = (1/pi) * integral of L(l) max(n.l, 0) dl, the
// radiance a white Lambertian surface of normal n reflects. Cosine-weighted Hammersley
// samples, each read from the source mip its solid angle covers (filtered importance
// sampling), so few samples give a smooth result.
#include "common/ibl.glsl"

#ifndef OUT_FORMAT
#define OUT_FORMAT rgba16f
#endif

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0) uniform samplerCube environment;  // with its mip chain
layout(set = 0, binding = 1, OUT_FORMAT) uniform writeonly image2DArray irradiance;

layout(push_constant) uniform Params {
    int faceSize;            // of the irradiance cube
    int samples;
    float environmentSize;   // face size of the environment's mip 0
    float lodBias;
} params;

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    if (texel.x >= params.faceSize || texel.y >= params.faceSize) return;
    vec2 st = (vec2(texel.xy) + 0.5) / float(params.faceSize);
    vec3 n = normalize(cubeToDirection(texel.z, st));
    mat3 frame = basisAround(n);
    uint count = uint(params.samples);
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < count; ++i) {
        vec3 local = sampleCosine(hammersley(i, count));
        float pdf = local.z / IBL_PI;
        float lod = sourceLod(pdf, float(count), params.environmentSize) + params.lodBias;
        sum += textureLod(environment, frame * local, lod).rgb;
    }
    imageStore(irradiance, texel, vec4(sum / float(count), 1.0));
}
