#version 450
#extension GL_GOOGLE_include_directive : require
// CubemapMipPass: one texel of the level written is the mean of the 2x2 texels of the level
// above that it covers. A bilinear tap at the target texel's centre, which is the shared
// corner of those four source texels, is exactly that mean (a box filter).
#include "common/ibl.glsl"

#ifndef OUT_FORMAT
#define OUT_FORMAT rgba16f
#endif

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0) uniform samplerCube source;  // the level above, alone
layout(set = 0, binding = 1, OUT_FORMAT) uniform writeonly image2DArray target;

layout(push_constant) uniform Params {
    int faceSize;  // of the level written
} params;

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    if (texel.x >= params.faceSize || texel.y >= params.faceSize) return;
    vec2 st = (vec2(texel.xy) + 0.5) / float(params.faceSize);
    vec3 dir = cubeToDirection(texel.z, st);
    imageStore(target, texel, vec4(textureLod(source, dir, 0.0).rgb, 1.0));
}
