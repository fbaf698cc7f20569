#version 450
#extension GL_GOOGLE_include_directive : require
// TonemappingComputePass: tonemap.frag's work as a compute shader, for GPUs whose fragment
// path is slow at fullscreen passes (docs/performance.md, NVIDIA H100). Storage images cannot
// be sRGB, so the shader always encodes sRGB (exactly: common/tonemap.glsl's srgbEncode).
// A group of 8x8 invocations covers a 16x16 tile, each invocation four pixels 8 apart, with
// its four loads before any store: on the H100 that is what brings the pass near its
// bandwidth bound (one pixel per invocation leaves too few bytes in flight).
#include "common/tonemap.glsl"

#ifndef OUT_FORMAT
#define OUT_FORMAT rgba8
#endif

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0) uniform sampler2D hdrInput;
#ifdef OUT_FORMAT_UNKNOWN
// A format without a GLSL qualifier (B8G8R8A8_UNORM): written through the view's format
// (shaderStorageImageWriteWithoutFormat).
layout(set = 0, binding = 1) uniform writeonly image2D outImage;
#else
layout(set = 0, binding = 1, OUT_FORMAT) uniform writeonly image2D outImage;
#endif
layout(push_constant) uniform Params {
    float exposureEv;
    int toneOperator;
} params;

void main() {
    ivec2 size = imageSize(outImage);
    ivec2 last = textureSize(hdrInput, 0) - 1;
    ivec2 base = ivec2(gl_WorkGroupID.xy) * 16 + ivec2(gl_LocalInvocationID.xy);
    const ivec2 offsets[4] = ivec2[4](ivec2(0, 0), ivec2(8, 0), ivec2(0, 8), ivec2(8, 8));
    // All four loads first (clamped, so an edge tile never reads outside the input), then
    // the stores that fall inside it. texelFetch, as tonemap.frag: no filtering can mix a NaN
    // neighbour into a finite pixel.
    vec3 hdr[4];
    for (int i = 0; i < 4; ++i) hdr[i] = texelFetch(hdrInput, min(base + offsets[i], last), 0).rgb;
    for (int i = 0; i < 4; ++i) {
        ivec2 p = base + offsets[i];
        if (any(greaterThanEqual(p, size))) continue;
        vec3 c = tonemap(hdr[i], params.exposureEv, params.toneOperator);
        imageStore(outImage, p, vec4(srgbEncode(c), 1.0));
    }
}
