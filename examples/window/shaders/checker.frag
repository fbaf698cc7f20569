#version 450
// CheckerPass: tiles of `tile` x `tile` pixels, colorA where (x / tile + y / tile) is even
// and colorB where it is odd, counted from the top-left pixel.
layout(push_constant) uniform Params {
    vec4 colorA;
    vec4 colorB;
    int tile;
} params;

layout(location = 0) in vec2 inUv;  // from skygraph's passes/fullscreen.vert (unused)
layout(location = 0) out vec4 outColor;

void main() {
    ivec2 cell = ivec2(gl_FragCoord.xy) / params.tile;
    outColor = ((cell.x + cell.y) & 1) == 0 ? params.colorA : params.colorB;
}
