#version 450
#extension GL_GOOGLE_include_directive : require
// PathTracePass: progressive path tracing of the scene's analytic spheres and planes, and of
// its glTF meshes through a BVH (passes/path_trace/triangle_bvh.hpp), with the forward pass's
// metal/rough GGX material (diffuse baseColor*(1-metallic)/pi plus GGX with
// Schlick Fresnel and height-correlated Smith, as common/brdf.glsl), lit by the environment:
// the equirect map when ENV_EQUIRECT = 1, else the procedural sky. The accumulation image
// holds the running MEAN of the samples in rgb and their count in alpha, so any reader
// (TonemappingPass) sees the current estimate directly.
#include "common/brdf.glsl"
// Compute shaders have no derivatives: leave out environment.glsl's equirectLod. The path
// tracer samples the equirect map's top level (one ray, no footprint).
#define ENVIRONMENT_NO_DERIVATIVES
#include "common/environment.glsl"

#ifndef ENV_EQUIRECT
#define ENV_EQUIRECT 0
#endif

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, rgba32f) uniform image2D accumulation;

struct Object {
    vec4 originSize;         // camera-relative centre (sphere) or point (plane); radius or half extent (<= 0: infinite)
    vec4 normalKind;         // plane normal; w: 0 sphere, 1 plane
    vec4 baseColorMetallic;
    vec4 roughnessAo;        // x: roughness, y: ao (unused: the path tracer finds occlusion itself)
};
layout(std430, set = 0, binding = 1) readonly buffer Objects {
    ivec4 count;  // x: objects
    Object objects[];
} scene;

#if ENV_EQUIRECT
layout(set = 0, binding = 2) uniform sampler2D environmentMap;
#endif

// The meshes: world-space triangles under a BVH whose leaves list triangles in `tris` order.
struct Node {
    vec3 lo;
    uint first;  // leaf: first triangle; interior: first child (the second follows it)
    vec3 hi;
    uint count;  // leaf: triangles; 0: interior
};
layout(std430, set = 0, binding = 3) readonly buffer Nodes { Node nodes[]; } bvh;
layout(std430, set = 0, binding = 4) readonly buffer Triangles { uvec4 tris[]; } mesh;  // xyz: vertices, w: material
struct Vertex {
    vec4 positionU;
    vec4 normalV;
    vec4 tangent;  // xyz, w: the bitangent's sign
};
layout(std430, set = 0, binding = 5) readonly buffer Vertices { Vertex verts[]; } vertices;
struct Material {
    vec4 baseColor;
    vec4 emissiveRoughness;
    vec4 metallicNormalScaleAlpha;  // x: metallic, y: normal scale (0: no normal texture), z: alpha threshold (< 0: opaque)
    ivec4 textures;                 // base colour, metallic-roughness, normal, emissive: slots of `textures`, -1 none
};
layout(std430, set = 0, binding = 6) readonly buffer Materials { Material materials[]; } mats;
// Textures as texels the shader filters itself (passes/path_trace/trace_geometry.hpp).
struct Texture {
    uint firstTexel;
    uint width;
    uint height;
    uint flags;  // bits 0-1: wrap in u, 2-3: in v (0 repeat, 1 clamp to edge, 2 mirrored repeat), 4: sRGB
};
layout(std430, set = 0, binding = 7) readonly buffer Textures { Texture entries[]; } textures;
layout(std430, set = 0, binding = 8) readonly buffer Texels { uint texels[]; } texels;  // RGBA8, R lowest

layout(push_constant) uniform Params {
    vec4 cameraToWorld[3];  // columns of the camera rotation
    vec4 projection;        // x: aspect * tan(fovY/2), y: tan(fovY/2), z: sin, w: cos of the environment rotation
    ivec4 frame;            // x: samples already accumulated (0: start over), y: samples this frame, z: max bounces, w: seed
    vec4 sun;               // xyz: towards the procedural sky's sun
    vec4 cameraPosition;    // xyz: the camera in the world (meshes are in world space); w: 1 when there are meshes
} params;

// PCG hash (Jarzynski & Olano 2020): decorrelated streams per pixel and sample.
uint pcg(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
uint rngState;
float random01() {
    rngState = pcg(rngState);
    return float(rngState >> 8) * (1.0 / 16777216.0);
}

vec3 environment(vec3 d) {
    d = rotateY(d, params.projection.z, params.projection.w);
#if ENV_EQUIRECT
    return textureLod(environmentMap, directionToEquirect(d), 0.0).rgb;
#else
    return proceduralSky(d, params.sun.xyz);
#endif
}

mat3 basisAround(vec3 n) {
    vec3 t = normalize(cross(abs(n.y) < 0.9 ? vec3(0, 1, 0) : vec3(1, 0, 0), n));
    return mat3(t, cross(n, t), n);
}

struct Hit {
    float t;       // -1: none
    vec3 normal;   // analytic objects: the surface normal
    int object;    // analytic object, or -1
    int triangle;  // mesh triangle, or -1
    vec2 bary;     // weights of the triangle's second and third vertices
};

int wrapTexel(int i, int size, uint mode) {
    if (mode == 1u) return clamp(i, 0, size - 1);
    if (mode == 2u) {
        int m = i % (2 * size);
        if (m < 0) m += 2 * size;
        return m < size ? m : 2 * size - 1 - m;
    }
    int m = i % size;
    return m < 0 ? m + size : m;
}

vec4 fetchTexel(Texture t, int x, int y) {
    vec4 c = unpackUnorm4x8(texels.texels[t.firstTexel + uint(y) * t.width + uint(x)]);
    if ((t.flags & 16u) != 0u)  // sRGB to linear before filtering, as an sRGB view does
        c.rgb = mix(c.rgb / 12.92, pow((c.rgb + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c.rgb));
    return c;
}

// Bilinear at mip 0, with the texture's wrap modes: what a linear sampler reads at LOD 0.
vec4 sampleTexture(int slot, vec2 uv) {
    if (slot < 0) return vec4(1.0);
    Texture t = textures.entries[slot];
    int w = int(t.width), h = int(t.height);
    vec2 p = uv * vec2(w, h) - 0.5;
    vec2 f = fract(p);
    ivec2 i0 = ivec2(floor(p));
    int x0 = wrapTexel(i0.x, w, t.flags & 3u), x1 = wrapTexel(i0.x + 1, w, t.flags & 3u);
    int y0 = wrapTexel(i0.y, h, (t.flags >> 2) & 3u), y1 = wrapTexel(i0.y + 1, h, (t.flags >> 2) & 3u);
    return mix(mix(fetchTexel(t, x0, y0), fetchTexel(t, x1, y0), f.x),
               mix(fetchTexel(t, x0, y1), fetchTexel(t, x1, y1), f.x), f.y);
}

// Möller-Trumbore; t in (tMin, tMax), and the alpha mask passed.
bool hitTriangle(uint index, vec3 o, vec3 d, float tMax, inout Hit hit) {
    uvec4 tri = mesh.tris[index];
    vec3 a = vertices.verts[tri.x].positionU.xyz, b = vertices.verts[tri.y].positionU.xyz,
         c = vertices.verts[tri.z].positionU.xyz;
    vec3 e1 = b - a, e2 = c - a, p = cross(d, e2);
    float det = dot(e1, p);
    if (abs(det) < 1e-20) return false;
    float inv = 1.0 / det;
    vec3 s = o - a;
    float u = dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) return false;
    vec3 q = cross(s, e1);
    float v = dot(d, q) * inv;
    if (v < 0.0 || u + v > 1.0) return false;
    float t = dot(e2, q) * inv;
    float scale = max(max(abs(a.x), abs(a.y)), max(abs(a.z), 1.0));
    if (t <= 1e-6 * scale || t >= tMax) return false;
    Material m = mats.materials[tri.w];
    if (m.metallicNormalScaleAlpha.z >= 0.0) {
        vec2 uv = (1.0 - u - v) * vec2(vertices.verts[tri.x].positionU.w, vertices.verts[tri.x].normalV.w) +
                  u * vec2(vertices.verts[tri.y].positionU.w, vertices.verts[tri.y].normalV.w) +
                  v * vec2(vertices.verts[tri.z].positionU.w, vertices.verts[tri.z].normalV.w);
        if (sampleTexture(m.textures.x, uv).a < m.metallicNormalScaleAlpha.z) return false;
    }
    hit.t = t;
    hit.triangle = int(index);
    hit.object = -1;
    hit.bary = vec2(u, v);
    return true;
}

// The nearest triangle along the world-space ray o + t d with t < hit.t (or any t when none).
void intersectMeshes(vec3 o, vec3 d, inout Hit hit) {
    if (params.cameraPosition.w < 0.5) return;
    vec3 invD = 1.0 / d;
    uint stack[48];
    int top = 0;
    stack[top++] = 0u;
    while (top > 0) {
        Node node = bvh.nodes[stack[--top]];
        vec3 t0 = (node.lo - o) * invD, t1 = (node.hi - o) * invD;
        vec3 near = min(t0, t1), far = max(t0, t1);
        float enter = max(max(near.x, near.y), max(near.z, 0.0));
        float leave = min(min(far.x, far.y), far.z);
        float tMax = hit.t < 0.0 ? 3.4e38 : hit.t;
        if (enter > leave || enter > tMax) continue;
        if (node.count > 0u) {
            for (uint i = 0u; i < node.count; ++i) hitTriangle(node.first + i, o, d, hit.t < 0.0 ? 3.4e38 : hit.t, hit);
        } else if (top + 2 <= 48) {
            stack[top++] = node.first;
            stack[top++] = node.first + 1u;
        }
    }
}

// Nearest hit along o + t d (o camera-relative), t > 0, analytic objects and meshes. The ray
// leaves analytic object `leaving` (-1: none), from inside it when `inside`: a plane, or a
// sphere left from outside, is never met again, so it is skipped, and only a sphere left from
// inside needs a least distance against meeting itself by float error (one scaled by the
// radius, for every ray, passed over ground nearer than a ten-thousandth of a large sphere's
// radius and hit its far side from within).
Hit intersect(vec3 o, vec3 d, int leaving, bool inside) {
    Hit hit;
    hit.t = -1.0;
    hit.object = -1;
    hit.triangle = -1;
    float best = 3.4e38;
    for (int i = 0; i < scene.count.x; ++i) {
        if (i == leaving && !inside) continue;
        Object obj = scene.objects[i];
        float t = -1.0;
        vec3 n;
        if (obj.normalKind.w < 0.5) {
            vec3 oc = o - obj.originSize.xyz;
            float b = dot(oc, d);
            // c = |oc|^2 - r^2 as (|oc| - r)(|oc| + r): no cancellation on the surface.
            float len = length(oc);
            float c = (len - obj.originSize.w) * (len + obj.originSize.w);
            float disc = b * b - c;
            if (disc < 0.0) continue;
            float s = sqrt(disc);
            float t0 = -b - s, t1 = -b + s;
            float tMin = i == leaving ? 1e-4 * max(obj.originSize.w, 1e-3) : 0.0;
            t = t0 > tMin ? t0 : (t1 > tMin ? t1 : -1.0);
            n = normalize(o + t * d - obj.originSize.xyz);
        } else {
            n = obj.normalKind.xyz;
            float dn = dot(d, n);
            if (abs(dn) < 1e-12) continue;
            t = dot(obj.originSize.xyz - o, n) / dn;
            if (obj.originSize.w > 0.0 && t > 0.0) {
                vec3 local = transpose(basisAround(n)) * (o + t * d - obj.originSize.xyz);
                if (abs(local.x) > obj.originSize.w || abs(local.y) > obj.originSize.w) t = -1.0;
            }
        }
        if (t > 0.0 && t < best) {
            best = t;
            hit.t = t;
            hit.normal = n;
            hit.object = i;
        }
    }
    intersectMeshes(o + params.cameraPosition.xyz, d, hit);
    return hit;
}

// What the path needs of the surface it hit.
struct Surface {
    vec3 normal;     // shading normal, towards the viewer
    vec3 offset;     // geometric normal on the viewer's side, to leave the surface along
    vec3 baseColor;
    float metallic;
    float roughness;
    vec3 emissive;
};

Surface surfaceAt(Hit hit, vec3 v) {
    Surface s;
    s.emissive = vec3(0.0);
    if (hit.object >= 0) {
        Object obj = scene.objects[hit.object];
        s.normal = dot(hit.normal, v) < 0.0 ? -hit.normal : hit.normal;  // planes are two-sided; a sphere seen from inside too
        s.offset = s.normal;
        s.baseColor = obj.baseColorMetallic.rgb;
        s.metallic = obj.baseColorMetallic.a;
        s.roughness = obj.roughnessAo.x;
        return s;
    }
    uvec4 tri = mesh.tris[hit.triangle];
    Vertex a = vertices.verts[tri.x], b = vertices.verts[tri.y], c = vertices.verts[tri.z];
    float wa = 1.0 - hit.bary.x - hit.bary.y;
    vec2 uv = wa * vec2(a.positionU.w, a.normalV.w) + hit.bary.x * vec2(b.positionU.w, b.normalV.w) +
              hit.bary.y * vec2(c.positionU.w, c.normalV.w);
    vec3 ng = normalize(cross(b.positionU.xyz - a.positionU.xyz, c.positionU.xyz - a.positionU.xyz));
    if (dot(ng, v) < 0.0) ng = -ng;
    vec3 n = normalize(wa * a.normalV.xyz + hit.bary.x * b.normalV.xyz + hit.bary.y * c.normalV.xyz);
    if (dot(n, v) < 0.0) n = -n;  // as the forward pass shows both faces
    Material m = mats.materials[tri.w];
    vec4 base = sampleTexture(m.textures.x, uv);
    vec4 mr = sampleTexture(m.textures.y, uv);
    s.baseColor = m.baseColor.rgb * base.rgb;
    s.metallic = m.metallicNormalScaleAlpha.x * mr.b;
    s.roughness = m.emissiveRoughness.a * mr.g;
    if (m.textures.z >= 0) {
        vec3 tn = sampleTexture(m.textures.z, uv).xyz * 2.0 - 1.0;
        tn.xy *= m.metallicNormalScaleAlpha.y;
        vec4 tangent = wa * a.tangent + hit.bary.x * b.tangent + hit.bary.y * c.tangent;
        vec3 t = tangent.xyz - n * dot(n, tangent.xyz);
        if (dot(t, t) > 1e-12) {
            t = normalize(t);
            vec3 bt = cross(n, t) * (a.tangent.w < 0.0 ? -1.0 : 1.0);
            n = normalize(t * tn.x + bt * tn.y + n * max(tn.z, 1e-3));
        }
    }
    s.normal = n;
    s.offset = ng;
    s.emissive = m.emissiveRoughness.rgb * sampleTexture(m.textures.w, uv).rgb;
    return s;
}

vec3 cosineSample(vec3 n) {
    float u = random01(), v = random01();
    float r = sqrt(u), phi = 2.0 * PI * v;
    return basisAround(n) * vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u)));
}

vec3 ggxHalfVector(vec3 n, float alpha) {
    float u = random01(), v = random01();
    float cosTheta = sqrt((1.0 - u) / (1.0 + (alpha * alpha - 1.0) * u));
    float sinTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta));
    float phi = 2.0 * PI * v;
    return basisAround(n) * vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}

vec3 tracePath(vec3 origin, vec3 dir) {
    vec3 radiance = vec3(0.0), throughput = vec3(1.0);
    int leaving = -1;
    bool inside = false;
    for (int bounce = 0; bounce <= params.frame.z; ++bounce) {
        Hit hit = intersect(origin, dir, leaving, inside);
        if (hit.t < 0.0) {
            radiance += throughput * environment(dir);
            break;
        }
        vec3 p = origin + hit.t * dir;
        vec3 v = -dir;
        Surface surface = surfaceAt(hit, v);
        radiance += throughput * surface.emissive;
        if (bounce == params.frame.z) break;  // out of bounces: the path carries nothing more
        vec3 n = surface.normal;
        vec3 baseColor = surface.baseColor;
        float metallic = surface.metallic;
        float alpha = clamp(surface.roughness, 0.045, 1.0);
        alpha *= alpha;
        vec3 f0 = mix(vec3(0.04), baseColor, metallic);
        vec3 diffuseColor = baseColor * (1.0 - metallic);
        // One lobe per bounce, picked by a fixed probability; each lobe's estimate is divided
        // by its probability, so the sum stays unbiased.
        float pDiffuse = metallic >= 1.0 ? 0.0 : 0.5;
        vec3 l;
        if (random01() < pDiffuse) {
            l = cosineSample(n);
            throughput *= diffuseColor / pDiffuse;  // (c / pi) * cos / (cos / pi)
        } else {
            vec3 h = ggxHalfVector(n, alpha);
            l = reflect(-v, h);
            float nl = dot(n, l), nv = max(dot(n, v), 1e-4), nh = max(dot(n, h), 1e-7), vh = max(dot(v, h), 1e-7);
            if (nl <= 0.0) break;
            // f * cos / pdf with pdf = D nh / (4 vh): F V 4 vh nl / nh.
            throughput *= fresnelSchlick(f0, vh) * smithVisibility(nv, nl, alpha) * 4.0 * vh * nl / nh /
                          (1.0 - pDiffuse);
        }
        if (dot(l, surface.offset) <= 0.0) break;  // a shading normal that sends the path into the surface
        float scale = max(max(abs(p.x), abs(p.y)), max(abs(p.z), 1.0));
        origin = p + surface.offset * (1e-4 * scale);
        dir = l;
        // Outward from a sphere when the side it leaves by is the outer one (hit.normal points
        // out of a sphere); a plane is never met again from either side.
        leaving = hit.object;
        inside = hit.object >= 0 && scene.objects[hit.object].normalKind.w < 0.5 && dot(surface.offset, hit.normal) < 0.0;
    }
    return radiance;
}

void main() {
    ivec2 size = imageSize(accumulation);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= size.x || pixel.y >= size.y) return;
    int already = params.frame.x;
    vec3 sum = vec3(0.0);
    for (int s = 0; s < params.frame.y; ++s) {
        rngState = pcg(uint(pixel.x) + pcg(uint(pixel.y) + pcg(uint(already + s) + uint(params.frame.w))));
        // Jittered in the pixel; NDC y up, as the skybox and pixelToNdc.
        vec2 ndc = (vec2(pixel) + vec2(random01(), random01())) / vec2(size) * 2.0 - 1.0;
        vec3 local = vec3(ndc.x * params.projection.x, -ndc.y * params.projection.y, -1.0);
        vec3 dir = normalize(params.cameraToWorld[0].xyz * local.x + params.cameraToWorld[1].xyz * local.y +
                             params.cameraToWorld[2].xyz * local.z);
        vec3 c = tracePath(vec3(0.0), dir);
        // A NaN or inf sample would poison the mean for good: it is dropped (counted as black).
        if (any(isnan(c)) || any(isinf(c))) c = vec3(0.0);
        sum += c;
    }
    vec4 previous = already > 0 ? imageLoad(accumulation, pixel) : vec4(0.0);
    float total = float(already + params.frame.y);
    vec3 mean = previous.rgb + (sum - previous.rgb * float(params.frame.y)) / total;
    imageStore(accumulation, pixel, vec4(mean, total));
}
