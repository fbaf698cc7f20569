#version 450
#extension GL_GOOGLE_include_directive : require
// FORWARD_IBL = 1: lit by the environment pipeline's products (split-sum); otherwise by the
// procedural sky's sun plus a hemispherical ambient term.
#include "common/brdf.glsl"
#include "common/environment.glsl"

#ifndef FORWARD_IBL
#define FORWARD_IBL 0
#endif

layout(push_constant) uniform Draw {
    mat4 viewProjection;
    vec4 originAndScale;
    vec4 baseColorMetallic;
    vec4 planeNormalRoughness;
    vec4 aoViewKind;
} draw;

#if FORWARD_IBL
layout(set = 0, binding = 0) uniform samplerCube irradianceMap;
layout(set = 0, binding = 1) uniform samplerCube prefilteredMap;
layout(set = 0, binding = 2) uniform sampler2D brdfLut;
#endif

layout(location = 0) in vec3 inRelativePosition;
layout(location = 1) in vec3 inNormal;
layout(location = 0) out vec4 outColor;

void main() {
    vec3 n = normalize(inNormal);
    vec3 v = normalize(-inRelativePosition);
    if (dot(n, v) < 0.0) n = -n;  // planes are two-sided
    vec3 baseColor = draw.baseColorMetallic.rgb;
    float metallic = draw.baseColorMetallic.a;
    float roughness = clamp(draw.planeNormalRoughness.w, 0.045, 1.0);
    float ao = draw.aoViewKind.x;
    int view = int(draw.aoViewKind.y + 0.5);
    if (view == 1) { outColor = vec4(n * 0.5 + 0.5, 1.0); return; }
    if (view == 2) { outColor = vec4(vec3(metallic), 1.0); return; }
    if (view == 3) { outColor = vec4(vec3(draw.planeNormalRoughness.w), 1.0); return; }
    if (view == 4) { outColor = vec4(vec3(ao), 1.0); return; }

    float alpha = roughness * roughness;
    vec3 f0 = mix(vec3(0.04), baseColor, metallic);
    vec3 diffuseColor = baseColor * (1.0 - metallic);
    float nv = max(dot(n, v), 1e-4);
#if FORWARD_IBL
    // Prefiltered mip m holds perceptual roughness m / (levels - 1) (docs/environment.md);
    // directions turn with the environment exactly as the skybox turns them.
    float s = sin(draw.aoViewKind.w), c = cos(draw.aoViewKind.w);
    vec3 r = rotateY(reflect(-v, n), s, c);
    float levels = float(textureQueryLevels(prefilteredMap) - 1);
    vec3 specular = textureLod(prefilteredMap, r, roughness * levels).rgb;
    vec2 ab = texture(brdfLut, vec2(nv, roughness)).rg;
    vec3 color = diffuseColor * texture(irradianceMap, rotateY(n, s, c)).rgb + specular * (f0 * ab.x + ab.y);
    color *= ao;
#else
    const vec3 sunDir = normalize(vec3(0.35, 0.45, -0.82));
    const vec3 sunRadiance = vec3(1.0, 0.9, 0.7) * 3.0;
    vec3 h = normalize(v + sunDir);
    float nl = max(dot(n, sunDir), 0.0);
    vec3 f = fresnelSchlick(f0, max(dot(v, h), 0.0));
    vec3 spec = f * ggxD(max(dot(n, h), 0.0), alpha) * smithVisibility(nv, nl, alpha);
    vec3 direct = (diffuseColor / PI * (1.0 - f) + spec) * sunRadiance * nl;
    vec3 ambient = mix(vec3(0.18, 0.16, 0.14), vec3(0.45, 0.6, 0.9), n.y * 0.5 + 0.5) * 0.6;
    vec3 color = direct + ambient * (diffuseColor + f0 * 0.25) * ao;
#endif
    if (draw.aoViewKind.z > 1.5) color += draw.planeNormalRoughness.rgb;  // a glTF mesh's emissive
    outColor = vec4(color, 1.0);
}
