// Environment lookups, mirroring include/skygraph/shading_math.hpp.
#ifndef SKYGRAPH_ENVIRONMENT_GLSL
#define SKYGRAPH_ENVIRONMENT_GLSL

const float PI = 3.14159265358979323846;

// u = 0.5 + atan2(x, -z) / 2pi, v = acos(y) / pi: -Z is the map's centre, +Y its top row.
vec2 directionToEquirect(vec3 d) {
    return vec2(0.5 + atan(d.x, -d.z) / (2.0 * PI), acos(clamp(d.y, -1.0, 1.0)) / PI);
}

// Horizontal rotation about +Y from a precomputed sine and cosine.
vec3 rotateY(vec3 d, float s, float c) { return vec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z); }

// Mip level for an equirect lookup from the angular size of the pixel footprint, not from
// derivatives of u: atan2's jump at the seam would otherwise select the smallest mip along a
// line at u = 0/1, and the 1/sin(theta) stretch would blur the poles. `dir` is normalized.
// Fragment shaders only (it takes derivatives): a compute shader that includes this file
// defines ENVIRONMENT_NO_DERIVATIVES first.
#ifndef ENVIRONMENT_NO_DERIVATIVES
float equirectLod(vec3 dir, float mapHeight) {
    float pixelAngle = max(length(dFdx(dir)), length(dFdy(dir)));
    return log2(max(pixelAngle * mapHeight / PI, 1e-8));
}
#endif

// `sunDir`: unit, towards the sun (the scene's; math::proceduralSunDirection by default).
vec3 proceduralSky(vec3 dirIn, vec3 sunDir) {
    vec3 d = normalize(dirIn);
    const vec3 zenith = vec3(0.16, 0.34, 0.82), horizon = vec3(0.75, 0.85, 1.0);
    const vec3 ground = vec3(0.18, 0.16, 0.14);
    float up = d.y;
    vec3 sky = up >= 0.0 ? mix(horizon, zenith, sqrt(up))
                         : mix(horizon * 0.5, ground, min(1.0, -up * 4.0));
    float cosSun = dot(d, sunDir);
    float glow = pow(max(cosSun, 0.0), 64.0) * 2.0;
    float disc = cosSun > cos(radians(0.6)) ? 400.0 : 0.0;
    return sky + vec3(1.0, 0.9, 0.7) * (glow + disc);
}

#endif
