// Metal/rough GGX (Karis 2013 conventions: alpha = roughness^2).
#ifndef SKYGRAPH_BRDF_GLSL
#define SKYGRAPH_BRDF_GLSL

float ggxD(float nh, float alpha) {
    float a2 = alpha * alpha;
    float d = nh * nh * (a2 - 1.0) + 1.0;
    return a2 / (3.14159265358979 * d * d);
}

// Height-correlated Smith visibility V = G / (4 n.l n.v).
float smithVisibility(float nv, float nl, float alpha) {
    float a2 = alpha * alpha;
    float v = nl * sqrt(nv * nv * (1.0 - a2) + a2);
    float l = nv * sqrt(nl * nl * (1.0 - a2) + a2);
    return 0.5 / max(v + l, 1e-7);
}

vec3 fresnelSchlick(vec3 f0, float vh) { return f0 + (1.0 - f0) * pow(1.0 - vh, 5.0); }

#endif
