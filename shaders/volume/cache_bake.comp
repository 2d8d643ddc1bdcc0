#version 450 core
// The scattered-light cache baked on the GPU (src/fog/scattered_light_bake.h): the estimator of
// the CPU bake, src/integrators/path_tracer.cpp VolumePathTracer::scatteredLight(), in single
// precision. Per texel (one invocation each) paths start at the texel's centre in uniform random
// directions; each path is the path tracer's transport: free paths by delta tracking, emission
// by the null-collision estimator at every tentative collision, at a real collision the volume
// chosen in proportion to its extinction, the weight times its albedo, next-event estimation
// toward every light with the transmittance by ratio tracking (Russian roulette below 0.1),
// Russian roulette on the weight from rouletteDepth events on, a new direction from
// Henyey-Greenstein; a path leaving the volumes' box sees the sky (ambient). Unlike the CPU, whose
// majorant is one for all space, the tracking runs against local majorants (src/fog/
// majorant_grid.h): a DDA walks the cells of the majorant grid and the tentative collisions are
// sampled per cell against its majorant [Novak18] (empty cells crossed at once), which leaves
// both estimators unbiased. A dispatch adds the samples [sampleBegin, sampleEnd) of the texels
// [cellBegin, cellBegin + cellCount) (or of the listed texels at those positions: the surface
// pass, more samples where surfaces read the cache) to their sums (the accumulator) and writes
// the P1 terms of the samples so far: mean radiance (rgb, a: luminance) and G = 3 x mean(Y (-d)). Random
// numbers: a PCG stream per (seed, texel, sample) [ONeill14], and each texel's sums add its
// samples in order, so the result depends on neither the dispatch split nor the device's
// scheduling.
#include "volume_common.glsl"
#include "cache_bake.h"
#ifdef VEIL_VOLUME_EMISSION
#include "volume_emission.glsl"
#endif

layout(local_size_x = VEIL_CACHE_BAKE_GROUP) in;

layout(std430, binding = VEIL_SSBO_CACHE_BAKE) buffer Accumulator {
    vec4 accumulator[]; // 2 per texel: sum L (rgb), sum Y^2 (a); sum Y (-d) (xyz), 0
};
// The surface pass (texelList != 0): the texels that surfaces read with a small footprint,
// which go on with more samples after every texel has its first ones (sorted indices).
layout(std430, binding = VEIL_SSBO_CACHE_TEXELS) readonly buffer TexelList {
    uint listedTexels[];
};
layout(binding = VEIL_IMG_CACHE_MEAN, rgba32f) uniform writeonly image3D cacheMean;
layout(binding = VEIL_IMG_CACHE_FLUX, rgba32f) uniform writeonly image3D cacheFlux;

uniform ivec3 dims;
uniform vec3 boxLo, boxHi; // the volumes' world box: the grid's and the paths' bounds
uniform int cellBegin, cellCount; // texels (with texelList: positions in listedTexels)
uniform int texelList;
uniform int sampleBegin, sampleEnd;
uniform uint seed;
// The majorant grid over [boxLo, boxHi]: per cell a bound of the extinction, times
// majorantScale (> 1: the R16F density textures round up to 2^-11 of the grid's values).
layout(binding = VEIL_TEX_CACHE_MAJORANT) uniform sampler3D majorantGrid;
uniform ivec3 majorantDims;
uniform float majorantScale;
uniform vec3 ambient; // render.ambient: what a path leaving the box sees
uniform int maxBounces, rouletteDepth;
// Lights (src/integrators/medium.cpp lightArrival()): type 0 directional, 1 point, 2 spot;
// radiance = colour x intensity; direction normalized; cone = cos(outer), cos(inner).
uniform int lightCount;
uniform int lightType[VEIL_CACHE_MAX_LIGHTS];
uniform vec3 lightRadiance[VEIL_CACHE_MAX_LIGHTS];
uniform vec3 lightPosition[VEIL_CACHE_MAX_LIGHTS];
uniform vec3 lightDirection[VEIL_CACHE_MAX_LIGHTS];
uniform vec2 lightCone[VEIL_CACHE_MAX_LIGHTS];

const float kFar = 1e30;

// ---- random numbers: PCG (RXS-M-XS output of a 32-bit LCG with a per-path stream) ----
uint rngState, rngInc;

uint pcgHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

void seedPath(uint cell, uint index) {
    uint k = pcgHash(pcgHash(pcgHash(seed) ^ cell) ^ index);
    rngState = k;
    rngInc = (pcgHash(k ^ 0x5ca77e7u) << 1u) | 1u;
}

// Uniform in [0, 1) with 24 random bits.
float uniform01() {
    rngState = rngState * 747796405u + rngInc;
    uint word = ((rngState >> ((rngState >> 28u) + 4u)) ^ rngState) * 277803737u;
    word = (word >> 22u) ^ word;
    return float(word >> 8u) * (1.0 / 16777216.0);
}

// ---- the medium ----
// Extinction at world point p, per volume in sig[], and the emitted radiance per unit length.
float localAt(vec3 p, out float sig[VEIL_VOLUME_SLOTS], out vec3 emitted) {
    float sigma = 0.0;
    emitted = vec3(0.0);
    for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i) {
        sig[i] = 0.0;
        if (i < volumeCount) {
            bool empty;
            vec3 pi = (volumes[i].worldToIndex * vec4(p, 1.0)).xyz;
            vec3 uvw = volumeCoord(i, pi, empty);
            if (empty) continue;
            float d = max(0.0, texture(volumeData[i], uvw).r);
            sig[i] = volumes[i].densityScale * d;
            sigma += sig[i];
#ifdef VEIL_VOLUME_EMISSION
            emitted += volumeEmitted(i, d, uvw);
#else
            emitted += d * volumes[i].emission;
#endif
        }
    }
    return sigma;
}

float extinctionAt(vec3 p) {
    float sigma = 0.0;
    for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i)
        if (i < volumeCount) {
            bool empty;
            vec3 pi = (volumes[i].worldToIndex * vec4(p, 1.0)).xyz;
            sigma += volumes[i].densityScale * max(0.0, sampleVolumeIndex(i, pi, empty));
        }
    return sigma;
}

// The part of the ray o + t d (t >= 0) inside the volumes' box; false when empty.
bool boxInterval(vec3 o, vec3 d, out float t0, out float t1) {
    t0 = 0.0;
    t1 = kFar;
    for (int k = 0; k < 3; ++k) {
        if (abs(d[k]) < 1e-20) {
            if (o[k] < boxLo[k] || o[k] > boxHi[k]) return false;
        } else {
            float a = (boxLo[k] - o[k]) / d[k], b = (boxHi[k] - o[k]) / d[k];
            t0 = max(t0, min(a, b));
            t1 = min(t1, max(a, b));
        }
    }
    return t0 < t1;
}

// ---- the walk through the majorant grid's cells (3D DDA) ----
struct Walk {
    float t, tEnd;     // the ray parameter reached, and where the walk ends
    ivec3 cell, step;  // the cell holding t; +-1 per axis (0: the ray runs parallel)
    vec3 tNext, tDelta; // where the ray crosses the cell's next boundary per axis; per cell
};

// The walk along o + t d (unit d) over the part of [0, tMax] inside the box; false when empty.
bool walkBegin(vec3 o, vec3 d, float tMax, out Walk w) {
    float t0, t1;
    if (!boxInterval(o, d, t0, t1) || t0 >= min(t1, tMax)) return false;
    w.t = t0;
    w.tEnd = min(t1, tMax);
    vec3 size = (boxHi - boxLo) / vec3(majorantDims);
    vec3 p = (o + d * t0 - boxLo) / size;
    w.cell = clamp(ivec3(floor(p)), ivec3(0), majorantDims - 1);
    for (int k = 0; k < 3; ++k) {
        if (abs(d[k]) < 1e-20) {
            w.step[k] = 0;
            w.tDelta[k] = kFar;
            w.tNext[k] = kFar;
        } else {
            w.step[k] = d[k] > 0.0 ? 1 : -1;
            w.tDelta[k] = size[k] / abs(d[k]);
            float toBound = d[k] > 0.0 ? float(w.cell[k] + 1) - p[k] : p[k] - float(w.cell[k]);
            w.tNext[k] = t0 + max(toBound, 0.0) * w.tDelta[k];
        }
    }
    return true;
}

// The next tentative collision of the walk: an exponential optical depth spent over the cells
// at their majorants (mu: the majorant where it ends, at w.t); false when the walk ends first.
bool walkNext(inout Walk w, out float mu) {
    float tau = -log(1.0 - uniform01());
    for (;;) {
        float tExit = min(min(min(w.tNext.x, w.tNext.y), w.tNext.z), w.tEnd);
        mu = texelFetch(majorantGrid, w.cell, 0).r * majorantScale;
        float depth = mu * (tExit - w.t);
        if (depth > tau) {
            w.t += tau / mu;
            return true;
        }
        tau -= depth;
        w.t = tExit;
        if (tExit >= w.tEnd) return false;
        if (w.tNext.x <= w.tNext.y && w.tNext.x <= w.tNext.z) {
            w.cell.x += w.step.x;
            w.tNext.x += w.tDelta.x;
        } else if (w.tNext.y <= w.tNext.z) {
            w.cell.y += w.step.y;
            w.tNext.y += w.tDelta.y;
        } else {
            w.cell.z += w.step.z;
            w.tNext.z += w.tDelta.z;
        }
        if (any(lessThan(w.cell, ivec3(0))) || any(greaterThanEqual(w.cell, majorantDims)))
            return false;
    }
}

// Ratio tracking [Novak14 sec. 4] from o along d up to tMax against the cells' majorants, with
// roulette below 0.1.
float transmittance(vec3 o, vec3 d, float tMax) {
    Walk w;
    if (!walkBegin(o, d, tMax, w)) return 1.0;
    float tr = 1.0, mu;
    while (walkNext(w, mu)) {
        tr *= 1.0 - extinctionAt(o + d * w.t) / mu;
        if (tr < 0.1) {
            if (uniform01() >= 0.5) return 0.0;
            tr *= 2.0;
        }
    }
    return tr;
}

// ---- optics (integrators/medium.h) ----
float sampleHenyeyGreensteinCos(float g, float u) {
    if (abs(g) < 1e-4) return 1.0 - 2.0 * u;
    float s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    return clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
}

vec3 scatterDirection(vec3 d, float g) {
    float c = sampleHenyeyGreensteinCos(g, uniform01());
    float s = sqrt(max(0.0, 1.0 - c * c));
    float phi = 2.0 * PI * uniform01();
    float sgn = d.z >= 0.0 ? 1.0 : -1.0; // copysign(1, d.z)
    float a = -1.0 / (sgn + d.z), b = d.x * d.y * a;
    vec3 t = vec3(1.0 + sgn * d.x * d.x * a, sgn * b, -sgn * d.x);
    vec3 bt = vec3(b, sgn + d.y * d.y * a, -d.y);
    return normalize(s * cos(phi) * t + s * sin(phi) * bt + c * d);
}

float cacheSmoothstep(float e0, float e1, float x) {
    float t = clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Light l seen from p: unit direction toward it, distance, irradiance before any medium.
vec3 lightArrival(int l, vec3 p, out vec3 toLight, out float distance) {
    vec3 e = lightRadiance[l];
    if (lightType[l] == 0) {
        toLight = -lightDirection[l];
        distance = kFar;
        return e;
    }
    vec3 v = lightPosition[l] - p;
    float d2 = max(dot(v, v), 1e-16);
    distance = sqrt(d2);
    toLight = v / distance;
    e /= d2;
    if (lightType[l] == 2)
        e *= cacheSmoothstep(lightCone[l].x, lightCone[l].y, dot(-toLight, lightDirection[l]));
    return e;
}

// ---- one path (VolumePathTracer::trace with escapeSeesAmbient) ----
vec3 tracePath(vec3 o, vec3 d) {
    vec3 radiance = vec3(0.0), weight = vec3(1.0);
    int events = 0;
    float sig[VEIL_VOLUME_SLOTS];
    for (;;) {
        Walk w;
        bool collided = false;
        float sigma = 0.0, mu;
        if (walkBegin(o, d, kFar, w))
            while (walkNext(w, mu)) {
                vec3 p = o + d * w.t;
                vec3 emitted;
                sigma = localAt(p, sig, emitted);
                radiance += weight * emitted / mu;
                if (uniform01() * mu < sigma) {
                    o = p;
                    collided = true;
                    break;
                }
            }
        if (!collided) return radiance + weight * ambient;
        if (events >= maxBounces) return radiance; // the path ends in the medium
        // The scattering volume, in proportion to its extinction at o.
        float pick = uniform01() * sigma;
        int vi = 0;
        bool chosen = false;
        for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i)
            if (i < volumeCount && !chosen) {
                if (i == volumeCount - 1 || pick < sig[i]) {
                    vi = i;
                    chosen = true;
                } else {
                    pick -= sig[i];
                }
            }
        float g = volumes[vi].anisotropy;
        weight *= volumes[vi].albedo;
        ++events;
        if (all(equal(weight, vec3(0.0)))) return radiance;
        // Next-event estimation toward every light.
        for (int l = 0; l < lightCount; ++l) {
            vec3 toLight;
            float distance;
            vec3 e = lightArrival(l, o, toLight, distance);
            if (all(equal(e, vec3(0.0)))) continue;
            float phase = henyeyGreenstein(dot(toLight, d), g);
            radiance += weight * e * phase * transmittance(o, toLight, distance);
        }
        if (events >= rouletteDepth) {
            float q = min(1.0, maxComponent(weight));
            if (q <= 0.0 || uniform01() >= q) return radiance;
            weight /= q;
        }
        d = scatterDirection(d, g);
    }
}

void main() {
    int k = int(gl_GlobalInvocationID.x);
    if (k >= cellCount) return;
    int i = texelList != 0 ? int(listedTexels[cellBegin + k]) : cellBegin + k;
    ivec3 c = ivec3(i % dims.x, (i / dims.x) % dims.y, i / (dims.x * dims.y));
    vec3 x = boxLo + (vec3(c) + 0.5) / vec3(dims) * (boxHi - boxLo);
    const vec3 lum = vec3(0.2126, 0.7152, 0.0722);
    vec4 sum = sampleBegin == 0 ? vec4(0.0) : accumulator[2 * i];
    vec4 flux = sampleBegin == 0 ? vec4(0.0) : accumulator[2 * i + 1];
    for (int s = sampleBegin; s < sampleEnd; ++s) {
        seedPath(uint(i), uint(s));
        // Uniform direction on the sphere, the path's first direction away from x.
        float z = 1.0 - 2.0 * uniform01(), phi = 2.0 * PI * uniform01();
        float r = sqrt(max(0.0, 1.0 - z * z));
        vec3 d = vec3(r * cos(phi), r * sin(phi), z);
        vec3 L = tracePath(x, d);
        float y = dot(L, lum);
        sum += vec4(L, y * y);
        flux.xyz -= y * d; // the arriving light travels along -d
    }
    accumulator[2 * i] = sum;
    accumulator[2 * i + 1] = flux;
    vec3 mean = sum.rgb / float(sampleEnd);
    imageStore(cacheMean, c, vec4(mean, dot(mean, lum)));
    imageStore(cacheFlux, c, vec4(3.0 * flux.xyz / float(sampleEnd), 0.0));
}
