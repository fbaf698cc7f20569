#version 450
// ForwardPass: objects are meshes in their own frame, placed camera-relative. The CPU
// subtracts the camera position in double precision, so a camera at 1e7 loses nothing.
// Spheres use a unit sphere mesh; planes a unit square in their tangent frame; glTF meshes
// come in world space (scale 1, origin = -camera position).
layout(location = 0) in vec3 inPosition;  // object-local
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) in vec4 inTangent;   // xyz unit, w: the bitangent's sign

layout(push_constant) uniform Draw {
    mat4 viewProjection;        // rotation-only view (camera at the origin) times projection
    vec4 originAndScale;        // xyz: object origin minus camera position; w: size (meshes: normal scale)
    vec4 baseColorMetallic;
    vec4 planeNormalRoughness;  // xyz: the plane's normal (planes), emissive (meshes); w: roughness
    vec4 aoViewKind;            // x: ao (meshes: occlusion strength), y: alpha threshold,
                                // z: kind (0 sphere, 1 plane, 2 mesh) + 8 * debug view (0 none, 1..4),
                                // w: environment rotation (rad)
} draw;

layout(location = 0) out vec3 outRelativePosition;
layout(location = 1) out vec3 outNormal;
layout(location = 2) out vec2 outUv;
layout(location = 3) out vec4 outTangent;

void main() {
    vec3 local = inPosition;
    vec3 normal = inNormal;
    int kind = int(draw.aoViewKind.z + 0.5) % 8;
    if (kind == 1) {
        vec3 n = draw.planeNormalRoughness.xyz;
        vec3 t = normalize(cross(abs(n.y) < 0.9 ? vec3(0, 1, 0) : vec3(1, 0, 0), n));
        vec3 b = cross(n, t);
        local = t * inPosition.x + b * inPosition.z;
        normal = n;
    }
    vec3 p = local * (kind == 2 ? 1.0 : draw.originAndScale.w) + draw.originAndScale.xyz;
    outRelativePosition = p;
    outNormal = normal;
    outUv = inUv;
    outTangent = inTangent;
    gl_Position = draw.viewProjection * vec4(p, 1.0);
}
