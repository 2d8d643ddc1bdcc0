#version 450 core
// The fog marcher (issue: OpenVDB density fields ray-marched as fog). Per pixel of the fog
// target (full, 1/2 or 1/4 resolution) from the eye to the opaque depth: extinction, single
// scattering with Henyey-Greenstein, albedo, emission, an ambient term, and light visibility
// = opaque shadow map x transmittance through the volumes (light_transmittance.comp) x
// homogeneous fog toward point and spot lights. Each step is integrated analytically
// (constant coefficients over the step), accumulated in registers and written once (001
// section 7.2); the frame then hands the result to the OIT technique's oitEmit().
#include "../common/camera.glsl"
#include "../common/lights.glsl"
#include "veil:light_visibility"
#include "volume_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_DEPTH) uniform sampler2D opaqueDepth;
layout(binding = VEIL_TEX_VOLUME_LIGHT) uniform sampler3D volumeLight[VEIL_MAX_VOLUMES];
// rgb = in-scattered + emitted radiance, a = representative view depth of the fog
layout(binding = VEIL_IMG_FOG_RADIANCE, rgba16f) uniform writeonly image2D fogRadiance;
// rgb = transmittance, a = view depth of the opaque surface behind (for upsampling)
layout(binding = VEIL_IMG_FOG_TRANSMITTANCE, rgba16f) uniform writeonly image2D fogTransmittance;

uniform mat4 invViewProjection;
uniform int resolutionDivisor;
uniform int steps;
uniform uint seed;
uniform bool jitter;
uniform int primaryLight; // light whose transmittance volumes were computed (-1: none)
uniform float globalDensity;
uniform vec3 globalAlbedo;
uniform float globalAnisotropy;

float hash(uvec3 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z;
    return float(v.x & 0xFFFFFFu) / 16777216.0;
}

// Distance along the ray to leave the 8^3 leaf containing world point P (index space of i).
float leafExit(int i, vec3 P, vec3 rd) {
    vec3 p = (volumes[i].worldToIndex * vec4(P, 1.0)).xyz;
    vec3 d = mat3(volumes[i].worldToIndex) * rd;
    vec3 leafLo = floor(p / float(kLeafSize)) * float(kLeafSize);
    vec3 bound = mix(leafLo, leafLo + float(kLeafSize), greaterThan(d, vec3(0.0)));
    float tMin = 1e30;
    for (int k = 0; k < 3; ++k)
        if (abs(d[k]) > 1e-12) tMin = min(tMin, (bound[k] - p[k]) / d[k]);
    return max(tMin, 0.0);
}

float volumeTransmittanceToLight(vec3 P) {
    for (int i = 0; i < volumeCount; ++i) {
        vec3 uvw = (volumes[i].worldToLight * vec4(P, 1.0)).xyz;
        if (all(greaterThanEqual(uvw, vec3(0.0))) && all(lessThanEqual(uvw, vec3(1.0))))
            return texture(volumeLight[i], uvw).r;
    }
    return 1.0;
}

void main() {
    ivec2 q = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(fogRadiance);
    if (q.x >= size.x || q.y >= size.y) return;
    ivec2 full = textureSize(opaqueDepth, 0);
    // Full-resolution pixel at the centre of this fog texel's block.
    ivec2 p = min(q * resolutionDivisor + resolutionDivisor / 2, full - 1);
    float depth = texelFetch(opaqueDepth, p, 0).r;
    vec2 ndc = (vec2(p) + 0.5) / vec2(full) * 2.0 - 1.0;
    vec4 a = invViewProjection * vec4(ndc, -1.0, 1.0);
    vec4 b = invViewProjection * vec4(ndc, depth * 2.0 - 1.0, 1.0);
    vec3 ro = a.xyz / a.w, re = b.xyz / b.w;
    float tEnd = length(re - ro);
    vec3 rd = (re - ro) / max(tEnd, 1e-20);
    vec3 forward = camera.cameraForward.xyz;
    float startDepth = dot(ro - camera.cameraPosition.xyz, forward);
    float opaqueViewDepth = startDepth + tEnd * dot(rd, forward);

    // The interval to march: all of [0, tEnd] with global fog, else the union of the volumes'.
    float t0 = 1e30, t1 = -1e30;
    if (globalDensity > 0.0) {
        t0 = 0.0;
        t1 = tEnd;
    }
    for (int i = 0; i < volumeCount; ++i) {
        vec2 iv = volumeBoxInterval(i, ro, rd);
        if (iv.x < iv.y) {
            t0 = min(t0, iv.x);
            t1 = max(t1, iv.y);
        }
    }
    t0 = max(t0, 0.0);
    t1 = min(t1, tEnd);

    vec3 radiance = vec3(0.0);
    float T = 1.0;
    float depthWeight = 0.0, depthSum = 0.0;
    if (t0 < t1) {
        float dt = (t1 - t0) / float(steps);
        float offset = jitter ? hash(uvec3(q, seed)) : 0.5;
        vec3 V = -rd;
        for (int s = 0; s < steps; ++s) {
            float t = t0 + (float(s) + offset) * dt;
            vec3 P = ro + rd * t;
            float sigma = globalDensity;
            vec3 scatterAlbedo = globalDensity * globalAlbedo; // sum of sigma_i * albedo_i
            vec3 emitted = vec3(0.0);
            bool allEmpty = globalDensity == 0.0;
            float sig[VEIL_MAX_VOLUMES];
            for (int i = 0; i < volumeCount; ++i) {
                bool empty;
                vec3 pi = (volumes[i].worldToIndex * vec4(P, 1.0)).xyz;
                float d = sampleVolumeIndex(i, pi, empty);
                allEmpty = allEmpty && empty;
                sig[i] = volumes[i].densityScale * d;
                sigma += sig[i];
                scatterAlbedo += sig[i] * volumes[i].albedo;
                emitted += d * volumes[i].emission;
            }
            if (allEmpty) {
                // Empty-space skipping: jump to the first step past the exit of this leaf.
                float exitT = 1e30;
                for (int i = 0; i < volumeCount; ++i) exitT = min(exitT, leafExit(i, P, rd));
                int next = int(ceil((t + exitT - t0) / dt - offset));
                s = max(s, next - 1);
                continue;
            }
            if (sigma <= 0.0 && all(equal(emitted, vec3(0.0)))) continue;
            // In-scattering: sum over lights of phase x incident radiance x visibility.
            vec3 inscatter = lighting.ambient.rgb * scatterAlbedo; // isotropic ambient radiance
            for (int l = 0; l < lighting.lightCount.x; ++l) {
                vec3 L;
                vec3 e = incidentRadiance(l, P, L);
                if (all(equal(e, vec3(0.0)))) continue;
                lightAttenuateInMedium(l, P, e); // the shadow technique's visibility
                float vis = 1.0;
                if (l == primaryLight) vis *= volumeTransmittanceToLight(P);
                if (globalDensity > 0.0 && int(lighting.lights[l].positionType.w) != VEIL_LIGHT_DIRECTIONAL)
                    vis *= exp(-globalDensity * length(lighting.lights[l].positionType.xyz - P));
                float cosTheta = dot(-L, V); // light travels along -L, leaves toward V
                vec3 phaseAlbedo = globalDensity * globalAlbedo *
                                   henyeyGreenstein(cosTheta, globalAnisotropy);
                for (int i = 0; i < volumeCount; ++i)
                    phaseAlbedo += sig[i] * volumes[i].albedo *
                                   henyeyGreenstein(cosTheta, volumes[i].anisotropy);
                inscatter += e * vis * phaseAlbedo;
            }
            // Constant coefficients over the step: integral of T(t) (S) dt in closed form.
            float stepT = exp(-sigma * dt);
            float integral = sigma > 1e-8 ? (1.0 - stepT) / sigma : dt;
            radiance += T * (inscatter + emitted) * integral;
            float viewDepth = startDepth + t * dot(rd, forward);
            float w = T * (1.0 - stepT);
            depthSum += w * viewDepth;
            depthWeight += w;
            T *= stepT;
            if (T < 1e-4) {
                T = 0.0;
                break;
            }
        }
    }
    float fogDepth = depthWeight > 0.0 ? depthSum / depthWeight : opaqueViewDepth;
    imageStore(fogRadiance, q, vec4(radiance, fogDepth));
    imageStore(fogTransmittance, q, vec4(vec3(T), opaqueViewDepth));
}
