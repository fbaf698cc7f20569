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
// A glTF material's textures; white (and a normal scale of 0) where it has none.
layout(set = 0, binding = 3) uniform sampler2D baseColorTexture;         // sRGB view
layout(set = 0, binding = 4) uniform sampler2D metallicRoughnessTexture; // G roughness, B metallic
layout(set = 0, binding = 5) uniform sampler2D normalTexture;            // tangent space
layout(set = 0, binding = 6) uniform sampler2D occlusionTexture;         // R
layout(set = 0, binding = 7) uniform sampler2D emissiveTexture;          // sRGB view

layout(location = 0) in vec3 inRelativePosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) in vec4 inTangent;
layout(location = 0) out vec4 outColor;

void main() {
    vec3 n = normalize(inNormal);
    vec3 v = normalize(-inRelativePosition);
    if (dot(n, v) < 0.0) n = -n;  // planes and double-sided meshes show both faces
    vec3 baseColor = draw.baseColorMetallic.rgb;
    float metallic = draw.baseColorMetallic.a;
    float perceptualRoughness = draw.planeNormalRoughness.w;
    float ao = draw.aoViewKind.x;
    vec3 emissive = vec3(0.0);
    int kindAndView = int(draw.aoViewKind.z + 0.5);
    int kind = kindAndView % 8, view = kindAndView / 8;
    if (kind == 2) {
        // glTF 2.0 metallic-roughness: each texture scales its factor.
        vec4 base = texture(baseColorTexture, inUv);
        if (base.a < draw.aoViewKind.y) discard;  // alpha mask: cutoff / the factor's alpha
        baseColor *= base.rgb;
        vec4 mr = texture(metallicRoughnessTexture, inUv);
        perceptualRoughness *= mr.g;
        metallic *= mr.b;
        vec3 tn = texture(normalTexture, inUv).xyz * 2.0 - 1.0;
        tn.xy *= draw.originAndScale.w;
        vec3 t = normalize(inTangent.xyz - n * dot(n, inTangent.xyz));
        vec3 b = cross(n, t) * (inTangent.w < 0.0 ? -1.0 : 1.0);
        n = normalize(t * tn.x + b * tn.y + n * max(tn.z, 1e-3));
        ao = 1.0 + ao * (texture(occlusionTexture, inUv).r - 1.0);
        emissive = draw.planeNormalRoughness.rgb * texture(emissiveTexture, inUv).rgb;
    }
    float roughness = clamp(perceptualRoughness, 0.045, 1.0);
    if (view == 1) { outColor = vec4(n * 0.5 + 0.5, 1.0); return; }
    if (view == 2) { outColor = vec4(vec3(metallic), 1.0); return; }
    if (view == 3) { outColor = vec4(vec3(perceptualRoughness), 1.0); return; }
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
    outColor = vec4(color + emissive, 1.0);
}
