#version 450
// VignettePass: darkens towards the corners, out = in * (1 - strength * d^2), where d is the
// distance from the centre in units of the half-diagonal (1 at the corners).
layout(set = 0, binding = 0) uniform sampler2D inputImage;
layout(push_constant) uniform Params {
    float strength;
} params;

layout(location = 0) in vec2 inUv;  // from skygraph's passes/fullscreen.vert
layout(location = 0) out vec4 outColor;

void main() {
    ivec2 size = textureSize(inputImage, 0);
    vec2 uv = gl_FragCoord.xy / vec2(size);
    float d = length(uv - 0.5) / length(vec2(0.5));
    vec4 c = texelFetch(inputImage, min(ivec2(gl_FragCoord.xy), size - 1), 0);
    outColor = vec4(c.rgb * (1.0 - params.strength * d * d), c.a);
}
