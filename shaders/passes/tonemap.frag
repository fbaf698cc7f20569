#version 450
#extension GL_GOOGLE_include_directive : require
// TonemappingPass: exposure 2^EV, a tone curve, and sRGB encoding unless the output format
// encodes in hardware (an *_SRGB attachment). One HDR texel per output pixel: texelFetch, so
// no filtering can mix a NaN neighbour into a finite pixel.
#include "common/tonemap.glsl"

layout(set = 0, binding = 0) uniform sampler2D hdrInput;
layout(push_constant) uniform Params {
    float exposureEv;
    int toneOperator;
    int encodeSrgb;  // 1 when the output is UNORM and the shader must encode
} params;

layout(location = 0) in vec2 inUv;  // fullscreen.vert's; texelFetch needs whole pixels instead
layout(location = 0) out vec4 outColor;

void main() {
    ivec2 size = textureSize(hdrInput, 0);
    ivec2 p = min(ivec2(gl_FragCoord.xy), size - 1);
    vec3 c = tonemap(texelFetch(hdrInput, p, 0).rgb, params.exposureEv, params.toneOperator);
    if (params.encodeSrgb != 0) c = srgbEncode(c);
    outColor = vec4(c, 1.0);
}
