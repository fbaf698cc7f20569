#version 450
#extension GL_GOOGLE_include_directive : require
// SKY_MODE is defined by the pass when it builds the pipeline: 0 procedural, 1 cubemap,
// 2 equirect, 3 a fade from one cubemap to another. Each mode is its own pipeline, so only
// the textures it samples are bound.
#include "common/environment.glsl"

#ifndef SKY_OUTPUT_DIRECTION
#define SKY_OUTPUT_DIRECTION 0
#endif
#ifndef SKY_MODE
#define SKY_MODE 0
#endif

layout(push_constant) uniform Sky {
    vec4 cameraToWorld[3];
    vec4 projection;   // x: aspect * tan(fovY/2), y: tan(fovY/2), z: sin, w: cos of rotation
    ivec4 mode;
    vec4 environment;  // x: equirect height in texels; y: how far the fade is from previousMap (0) to environmentMap (1)
    vec4 sun;          // xyz: towards the procedural sky's sun
} sky;

#if SKY_MODE == 1 || SKY_MODE == 3
layout(set = 0, binding = 0) uniform samplerCube environmentMap;
#elif SKY_MODE == 2
layout(set = 0, binding = 0) uniform sampler2D environmentMap;
#endif
#if SKY_MODE == 3
layout(set = 0, binding = 1) uniform samplerCube previousMap;
#endif

layout(location = 0) in vec3 inDirection;
layout(location = 0) out vec4 outColor;

void main() {
    vec3 d = rotateY(normalize(inDirection), sky.projection.z, sky.projection.w);
#if SKY_OUTPUT_DIRECTION
    outColor = vec4(d, 1.0);
    return;
#endif
#if SKY_MODE == 1
    vec3 c = texture(environmentMap, d).rgb;
#elif SKY_MODE == 3
    vec3 c = texture(environmentMap, d).rgb;
    // Uniform across the draw: a finished fade costs no second fetch.
    if (sky.environment.y < 1.0) c = mix(texture(previousMap, d).rgb, c, sky.environment.y);
#elif SKY_MODE == 2
    vec3 c = textureLod(environmentMap, directionToEquirect(d), equirectLod(d, sky.environment.x)).rgb;
#else
    vec3 c = proceduralSky(d, sky.sun.xyz);
#endif
    outColor = vec4(c, 1.0);
}
