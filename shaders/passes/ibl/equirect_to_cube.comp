#version 450
#extension GL_GOOGLE_include_directive : require
// EquirectToCubemapPass: every texel of the six faces averages supersample x supersample
// bilinear taps of the equirect map, placed at the centres of an even sub-texel grid, so
// the texel approximates the mean radiance over its footprint. One invocation per texel,
// z = face (Vulkan face order +X,-X,+Y,-Y,+Z,-Z).
#include "common/ibl.glsl"

#ifndef OUT_FORMAT
#define OUT_FORMAT rgba16f
#endif

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0) uniform sampler2D equirect;  // repeat in u, clamp in v
layout(set = 0, binding = 1, OUT_FORMAT) uniform writeonly image2DArray cubemap;

layout(push_constant) uniform Params {
    int faceSize;
    int supersample;
} params;

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    if (texel.x >= params.faceSize || texel.y >= params.faceSize) return;
    int n = params.supersample;
    vec3 sum = vec3(0.0);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            vec2 st = (vec2(texel.xy) + (vec2(i, j) + 0.5) / float(n)) / float(params.faceSize);
            vec3 dir = normalize(cubeToDirection(texel.z, st));
            sum += textureLod(equirect, equirectCoordinate(dir), 0.0).rgb;
        }
    imageStore(cubemap, texel, vec4(sum / float(n * n), 1.0));
}
