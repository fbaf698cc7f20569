#version 450
// SkyboxPass: a fullscreen triangle at z = 0, the reverse-Z far plane, so that a
// GREATER_OR_EQUAL test against the cleared depth (0) passes only where nothing was drawn.
// The view ray comes from the camera's rotation alone (never its position), so it stays
// exact at any distance from the origin; it is linear in NDC, so interpolation is exact too.
layout(push_constant) uniform Sky {
    vec4 cameraToWorld[3];  // columns of the rotation (camera -> world)
    vec4 projection;        // x: aspect * tan(fovY/2), y: tan(fovY/2), z: sin, w: cos of rotation
    ivec4 mode;             // x: 0 procedural, 1 cubemap, 2 equirect
    vec4 environment;       // x: equirect height in texels
    vec4 sun;               // xyz: towards the procedural sky's sun
} sky;

layout(location = 0) out vec3 outDirection;

void main() {
    vec2 ndc = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2) * 2.0 - 1.0;
    mat3 r = mat3(sky.cameraToWorld[0].xyz, sky.cameraToWorld[1].xyz, sky.cameraToWorld[2].xyz);
    outDirection = r * vec3(ndc.x * sky.projection.x, -ndc.y * sky.projection.y, -1.0);
    gl_Position = vec4(ndc, 0.0, 1.0);
}
