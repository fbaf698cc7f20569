#version 450
// ForwardPass: objects are meshes in their own frame, placed camera-relative. The CPU
// subtracts the camera position in double precision, so a camera at 1e7 loses nothing.
layout(location = 0) in vec3 inPosition;  // object-local
layout(location = 1) in vec3 inNormal;

layout(push_constant) uniform Draw {
    mat4 viewProjection;    // rotation-only view (camera at the origin) times projection
    vec4 originAndScale;    // xyz: object origin minus camera position; w: uniform scale
    vec4 baseColorMetallic;
    vec4 roughnessAoView;   // x: roughness, y: ao, z: debug view (0 none, 1..4)
} draw;

layout(location = 0) out vec3 outRelativePosition;
layout(location = 1) out vec3 outNormal;

void main() {
    vec3 p = inPosition * draw.originAndScale.w + draw.originAndScale.xyz;
    outRelativePosition = p;
    outNormal = inNormal;
    gl_Position = draw.viewProjection * vec4(p, 1.0);
}
