// The medium along a fog ray, shared by the marchers (fog_march.comp: one result per pixel;
// fog_segments.comp: one per segment between the surfaces of `reference`): the ray of a
// pixel through the opaque depth, the interval of the volumes on it, and per sample the
// extinction and the source term (single scattering with Henyey-Greenstein toward every
// light, times the shadow technique's visibility, the volumes' transmittance toward the
// primary light and homogeneous fog toward point and spot lights; albedo; emission; ambient).
#include "../common/camera.glsl"
#include "../common/lights.glsl"
#include "veil:light_visibility"
#include "volume_common.glsl"

layout(binding = VEIL_TEX_DEPTH) uniform sampler2D opaqueDepth;
layout(binding = VEIL_TEX_VOLUME_LIGHT) uniform sampler3D volumeLight[VEIL_VOLUME_SLOTS];

uniform mat4 invViewProjection;
uniform int steps;
uniform uint seed;
uniform bool jitter;
uniform int primaryLight; // light whose transmittance volumes were computed (-1: none)
uniform float globalDensity;
uniform vec3 globalAlbedo;
uniform float globalAnisotropy;
// Multiple scattering by octaves [Wrenninge13], [Hillaire16]: octave n scatters with
// the extinction toward the light times a^n, the scattering times b^n and the anisotropy times
// c^n (octaveParams = (a, b, c)); 1 octave is single scattering. ambientScale scales the
// isotropic ambient (sky) in-scattering.
uniform int octaves;
uniform vec3 octaveParams;
uniform float ambientScale;
#ifdef VEIL_OCTAVE_RADIUS
// Depth-aware octaves (render.fog_octave_radius, docs/volumes.md): octave n >= 1 is also
// weighted by w^n, w = 1 - exp(-octaveRadius x the extinction averaged over the 8^3-voxel
// cells around the sample): thin wisps keep single scattering, the core keeps every octave.
uniform float octaveRadius;
layout(binding = VEIL_TEX_VOLUME_NEIGHBOURHOOD) uniform sampler3D volumeNeighbourhood[VEIL_VOLUME_SLOTS];

// Mean unscaled density of volume i around index-space point p (grid/neighbourhood.h: cell
// centres at 8k + 3.5, zero border).
float neighbourhoodMean(int i, vec3 p) {
    vec3 size = vec3(textureSize(volumeNeighbourhood[i], 0));
    vec3 c = (p - 3.5) / 8.0 - vec3(volumes[i].cellOrigin);
    return texture(volumeNeighbourhood[i], (c + 0.5) / size).r;
}
#endif

// The scattered-light cache (VEIL_SCATTERED_LIGHT): the in-scattered radiance toward V for
// phase anisotropy g is mean x (1 + g G.V / mean_Y).
#include "scattered_light.glsl"

#ifdef VEIL_VOLUME_EMISSION
#include "volume_emission.glsl"
#endif

float hash(uvec3 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z;
    return float(v.x & 0xFFFFFFu) / 16777216.0;
}

float volumeTransmittanceToLight(vec3 P) {
    for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i)
        if (i < volumeCount) {
            vec3 uvw = (volumes[i].worldToLight * vec4(P, 1.0)).xyz;
            if (all(greaterThanEqual(uvw, vec3(0.0))) && all(lessThanEqual(uvw, vec3(1.0))))
                return texture(volumeLight[i], uvw).r;
        }
    return 1.0;
}

struct FogRay {
    vec3 ro, rd;            // world origin (near plane) and unit direction
    float tEnd;             // ray parameter of the opaque surface
    float startDepth;       // view depth of ro
    float axial;            // view depth per unit of t (dot(rd, camera forward))
    float opaqueViewDepth;  // view depth of the opaque surface
    float t0, t1;           // interval to march (empty when t0 >= t1)
};

// The ray through full-resolution pixel p and the interval to march: all of [0, tEnd] with
// global fog, else the union of the volumes' boxes.
FogRay fogRay(ivec2 p) {
    FogRay r;
    ivec2 full = textureSize(opaqueDepth, 0);
    float depth = texelFetch(opaqueDepth, p, 0).r;
    vec2 ndc = (vec2(p) + 0.5) / vec2(full) * 2.0 - 1.0;
    vec4 a = invViewProjection * vec4(ndc, -1.0, 1.0);
    vec4 b = invViewProjection * vec4(ndc, depth * 2.0 - 1.0, 1.0);
    r.ro = a.xyz / a.w;
    vec3 re = b.xyz / b.w;
    r.tEnd = length(re - r.ro);
    r.rd = (re - r.ro) / max(r.tEnd, 1e-20);
    vec3 forward = camera.cameraForward.xyz;
    r.startDepth = dot(r.ro - camera.cameraPosition.xyz, forward);
    r.axial = dot(r.rd, forward);
    r.opaqueViewDepth = r.startDepth + r.tEnd * r.axial;
    float t0 = 1e30, t1 = -1e30;
    if (globalDensity > 0.0) {
        t0 = 0.0;
        t1 = r.tEnd;
    }
    for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i)
        if (i < volumeCount) {
            vec2 iv = volumeBoxInterval(i, r.ro, r.rd);
            if (iv.x < iv.y) {
                t0 = min(t0, iv.x);
                t1 = max(t1, iv.y);
            }
        }
    r.t0 = max(t0, 0.0);
    r.t1 = min(t1, r.tEnd);
    return r;
}

// The medium at world point P seen along direction -V: extinction sigma and source
// (in-scattered + emitted radiance per unit length). Returns false where every volume's leaf is
// empty (and there is no global fog): the caller skips to the next leaf with leafExit().
bool fogMedium(vec3 P, vec3 V, out float sigma, out vec3 source) {
    sigma = globalDensity;
    source = vec3(0.0);
    vec3 scatterAlbedo = globalDensity * globalAlbedo; // sum of sigma_i * albedo_i
    vec3 emitted = vec3(0.0);
    bool allEmpty = globalDensity == 0.0;
    float octaveWeight = 1.0;
#ifdef VEIL_OCTAVE_RADIUS
    float localSigma = 0.0;
#endif
    float sig[VEIL_VOLUME_SLOTS];
    for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i) {
        sig[i] = 0.0;
        if (i < volumeCount) {
            bool empty;
            vec3 pi = (volumes[i].worldToIndex * vec4(P, 1.0)).xyz;
#ifdef VEIL_VOLUME_EMISSION
            vec3 uvw = volumeCoord(i, pi, empty);
            float d = empty ? 0.0 : texture(volumeData[i], uvw).r;
            if (!empty) emitted += volumeEmitted(i, d, uvw);
#else
            float d = sampleVolumeIndex(i, pi, empty);
            emitted += d * volumes[i].emission;
#endif
            allEmpty = allEmpty && empty;
            sig[i] = volumes[i].densityScale * d;
#ifdef VEIL_OCTAVE_RADIUS
            localSigma += volumes[i].densityScale * neighbourhoodMean(i, pi);
#endif
            sigma += sig[i];
            scatterAlbedo += sig[i] * volumes[i].albedo;
        }
    }
    if (allEmpty) return false;
    if (sigma <= 0.0 && all(equal(emitted, vec3(0.0)))) return true;
#ifdef VEIL_OCTAVE_RADIUS
    octaveWeight = 1.0 - exp(-octaveRadius * localSigma);
#endif
    // In-scattering: sum over lights of phase x incident radiance x visibility.
#ifdef VEIL_SCATTERED_LIGHT
    // Light scattered before and the sky, from the cache (no ambient term: the sky is in it).
    vec3 inscatter = vec3(0.0);
    {
        vec3 uvw = (P - scatteredLo) / (scatteredHi - scatteredLo);
        vec4 m = texture(scatteredMean, uvw);
        float gv = m.a > 0.0 ? dot(texture(scatteredFlux, uvw).xyz, V) / m.a : 0.0;
        for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i)
            if (i < volumeCount)
                inscatter += m.rgb * (sig[i] * volumes[i].albedo) *
                             max(0.0, 1.0 + volumes[i].anisotropy * gv);
    }
#else
    vec3 inscatter = lighting.ambient.rgb * scatterAlbedo * ambientScale; // isotropic ambient
#endif
    for (int l = 0; l < lighting.lightCount.x; ++l) {
        vec3 L;
        vec3 e = incidentRadiance(l, P, L);
        if (all(equal(e, vec3(0.0)))) continue;
        lightAttenuateInMedium(l, P, e); // the shadow technique's visibility
        // Transmittance toward the light through the volumes and the homogeneous fog; octave n
        // raises it to the power a^n (its extinction times a^n).
        float volumeT = l == primaryLight ? volumeTransmittanceToLight(P) : 1.0;
        float fogTau = 0.0;
        if (globalDensity > 0.0 && int(lighting.lights[l].positionType.w) != VEIL_LIGHT_DIRECTIONAL)
            fogTau = globalDensity * length(lighting.lights[l].positionType.xyz - P);
        float cosTheta = dot(-L, V); // light travels along -L, leaves toward V
        float an = 1.0, bn = 1.0, cn = 1.0;
        for (int n = 0; n < octaves; ++n) {
            float vis = n == 0 ? volumeT * exp(-fogTau)
                               : exp2(an * log2(max(volumeT, 1e-30))) * exp(-an * fogTau);
            vec3 phaseAlbedo = globalDensity * globalAlbedo *
                               henyeyGreenstein(cosTheta, cn * globalAnisotropy);
            for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i)
                if (i < volumeCount)
                    phaseAlbedo += sig[i] * volumes[i].albedo *
                                   henyeyGreenstein(cosTheta, cn * volumes[i].anisotropy);
            inscatter += e * (vis * bn) * phaseAlbedo;
            an *= octaveParams.x;
            bn *= octaveParams.y * octaveWeight;
            cn *= octaveParams.z;
        }
    }
    source = inscatter + emitted;
    return true;
}

// The first step index past the exit of the leaf at P (empty-space skipping), for steps of
// dt from t0 with sample offset `offset`.
int fogSkipEmptyLeaf(vec3 P, vec3 rd, float t, float t0, float dt, float offset) {
    return firstStepPast(t, volumesLeafExit(P, rd), t0, dt, offset);
}
