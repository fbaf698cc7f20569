// Tone mapping, mirroring include/skygraph/shading_math.hpp line for line (tests compare the
// two within one 8-bit code).
#ifndef SKYGRAPH_TONEMAP_GLSL
#define SKYGRAPH_TONEMAP_GLSL

#define TONE_ACES_NARKOWICZ 0
#define TONE_ACES_HILL 1
#define TONE_KHRONOS_PBR_NEUTRAL 2
#define TONE_PASSTHROUGH 3

// NaN -> 0, negatives -> 0, above fp16 max (and +inf) -> fp16 max. Comparisons, not clamp():
// clamp() is undefined for NaN in GLSL and in practice lets it through.
float sanitizeHdr(float x) {
    if (isnan(x)) return 0.0;
    if (!(x > 0.0)) return 0.0;
    return x < 65504.0 ? x : 65504.0;
}
vec3 sanitizeHdr(vec3 c) { return vec3(sanitizeHdr(c.r), sanitizeHdr(c.g), sanitizeHdr(c.b)); }

float acesNarkowicz(float x) {
    const float a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

vec3 acesHill(vec3 rgb) {
    // Rows as written in BakingLab; GLSL mat3 constructors take columns, hence transpose.
    const mat3 inputMat = transpose(mat3(0.59719, 0.35458, 0.04823, 0.07600, 0.90834, 0.01566,
                                         0.02840, 0.13383, 0.83777));
    const mat3 outputMat = transpose(mat3(1.60475, -0.53108, -0.07367, -0.10208, 1.10813, -0.00605,
                                          -0.00327, -0.07276, 1.07602));
    vec3 v = inputMat * rgb;
    v = (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081);
    return clamp(outputMat * v, 0.0, 1.0);
}

vec3 khronosPbrNeutral(vec3 c) {
    const float startCompression = 0.8 - 0.04, desaturation = 0.15;
    float x = min(c.r, min(c.g, c.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    c -= offset;
    float peak = max(c.r, max(c.g, c.b));
    if (peak < startCompression) return c;
    const float d = 1.0 - startCompression;
    float newPeak = 1.0 - d * d / (peak + d - startCompression);
    c *= newPeak / peak;
    float g = 1.0 - 1.0 / (desaturation * (peak - newPeak) + 1.0);
    return mix(c, vec3(newPeak), g);
}

vec3 tonemap(vec3 hdr, float exposureEv, int op) {
    hdr = sanitizeHdr(hdr);
    if (op == TONE_PASSTHROUGH) return clamp(hdr, 0.0, 1.0);
    hdr = sanitizeHdr(hdr * exp2(clamp(exposureEv, -64.0, 64.0)));
    if (op == TONE_ACES_HILL) return acesHill(hdr);
    if (op == TONE_KHRONOS_PBR_NEUTRAL) return clamp(khronosPbrNeutral(hdr), 0.0, 1.0);
    return vec3(acesNarkowicz(hdr.r), acesNarkowicz(hdr.g), acesNarkowicz(hdr.b));
}

float srgbEncode(float linear) {
    linear = clamp(linear, 0.0, 1.0);
    return linear <= 0.0031308 ? linear * 12.92 : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}
vec3 srgbEncode(vec3 c) { return vec3(srgbEncode(c.r), srgbEncode(c.g), srgbEncode(c.b)); }

#endif
