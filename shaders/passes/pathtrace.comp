#version 450
#extension GL_GOOGLE_include_directive : require
// PathTracePass: progressive path tracing of the scene's analytic spheres and planes with the
// forward pass's metal/rough GGX material (diffuse baseColor*(1-metallic)/pi plus GGX with
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

layout(push_constant) uniform Params {
    vec4 cameraToWorld[3];  // columns of the camera rotation
    vec4 projection;        // x: aspect * tan(fovY/2), y: tan(fovY/2), z: sin, w: cos of the environment rotation
    ivec4 frame;            // x: samples already accumulated (0: start over), y: samples this frame, z: max bounces, w: seed
    vec4 sun;               // xyz: towards the procedural sky's sun
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

// Nearest hit along o + t d, t > tMin: returns t (or -1), the normal and the object index.
float intersect(vec3 o, vec3 d, out vec3 normal, out int hitIndex) {
    float best = 3.4e38;
    hitIndex = -1;
    for (int i = 0; i < scene.count.x; ++i) {
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
            float tMin = 1e-4 * max(obj.originSize.w, 1e-3);
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
            normal = n;
            hitIndex = i;
        }
    }
    return hitIndex >= 0 ? best : -1.0;
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
    for (int bounce = 0; bounce <= params.frame.z; ++bounce) {
        vec3 n;
        int index;
        float t = intersect(origin, dir, n, index);
        if (t < 0.0) {
            radiance += throughput * environment(dir);
            break;
        }
        if (bounce == params.frame.z) break;  // out of bounces: the path carries nothing more
        Object obj = scene.objects[index];
        vec3 p = origin + t * dir;
        vec3 v = -dir;
        if (dot(n, v) < 0.0) n = -n;  // planes are two-sided; a sphere seen from inside too
        vec3 baseColor = obj.baseColorMetallic.rgb;
        float metallic = obj.baseColorMetallic.a;
        float alpha = clamp(obj.roughnessAo.x, 0.045, 1.0);
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
        float scale = max(max(abs(p.x), abs(p.y)), max(abs(p.z), 1.0));
        origin = p + n * (1e-4 * scale);
        dir = l;
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
