// Microfacet BRDF: GGX distribution, height-correlated Smith visibility, Schlick Fresnel.
#include "math.glsl"

struct SurfaceMaterial {
    vec3 baseColor;
    float roughness;
    float metalness;
    vec3 emission;
    float alpha;
    vec3 transmission;
};

vec3 fresnelSchlick(vec3 f0, float cosTheta) {
    return f0 + (vec3(1.0) - f0) * pow(1.0 - saturate(cosTheta), 5.0);
}

float ggxD(float NdotH, float a2) {
    float d = NdotH * NdotH * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// V = G / (4 N.L N.V), height-correlated Smith for GGX.
float smithVisibility(float NdotL, float NdotV, float a2) {
    float gv = NdotL * sqrt(NdotV * NdotV * (1.0 - a2) + a2);
    float gl = NdotV * sqrt(NdotL * NdotL * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-7);
}

// Reflected radiance factor f(l,v) * N.L for unit incident radiance. `diffuseWeight` scales the
// Lambert lobe (1 - max T for transmissive surfaces: light that is transmitted is not diffused).
vec3 evaluateBrdfCos(SurfaceMaterial m, vec3 N, vec3 V, vec3 L, float diffuseWeight) {
    float NdotL = dot(N, L);
    if (NdotL <= 0.0) return vec3(0.0);
    float NdotV = max(dot(N, V), 1e-4);
    vec3 H = normalize(L + V);
    float NdotH = saturate(dot(N, H));
    float alphaR = max(m.roughness * m.roughness, 1e-3); // perceptual roughness squared
    float a2 = alphaR * alphaR;
    vec3 f0 = mix(vec3(0.04), m.baseColor, m.metalness);
    vec3 F = fresnelSchlick(f0, saturate(dot(L, H)));
    vec3 specular = ggxD(NdotH, a2) * smithVisibility(NdotL, NdotV, a2) * F;
    vec3 kd = (vec3(1.0) - F) * (1.0 - m.metalness) * diffuseWeight;
    vec3 diffuse = kd * m.baseColor / PI;
    return (diffuse + specular) * NdotL;
}
