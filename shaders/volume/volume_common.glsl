// Density volumes on the GPU (src/fog/gpu_volume.h): brick atlas + indirection, or dense.
#include "../common/bindings.h"
#include "../common/math.glsl"

struct VolumeInfo {
    mat4 worldToIndex;
    mat4 worldToLight;   // world -> [0,1]^3 of this volume's light-transmittance texture
    vec3 indexMin;       // index-space bounds of the stored data (voxel centres at integers)
    vec3 indexMax;
    ivec3 leafOrigin;    // leaf coordinate of indirection texel (0,0,0)
    ivec3 bricksPerAxis; // atlas layout; (0,0,0) for the dense path
    ivec3 cellOrigin;    // cell (index / 8) of texel (0,0,0) of the neighbourhood-mean texture
    float densityScale;
    vec3 albedo;
    float anisotropy;    // Henyey-Greenstein g
    vec3 emission;       // radiance emitted per unit length per unit density
    // Emission channel (fog_medium.glsl): 0 none (emission x density), 1 emission grid
    // (emission x value), 2 temperature grid (blackbody), 3 colour emission grid (emission x
    // rgb); temperature = (kelvin per unit,
    // kelvin offset, temperature_intensity x density_scale).
    int emissionMode;
    vec3 temperature;
};

uniform VolumeInfo volumes[VEIL_MAX_VOLUMES];
uniform int volumeCount;

// Sampler slots per array. The fog's programs define it to the scene's number of grid volumes
// (src/fog/fog_pass.cpp) and loop `for (i < VEIL_VOLUME_SLOTS) if (i < volumeCount)`, so
// the loops unroll and every texture is indexed by a constant: on llvmpipe a sampler array
// indexed by a non-constant runs the whole texture fetch once per SIMD lane, and fewer declared samplers keep the program under its per-stage sampler limits.
#ifndef VEIL_VOLUME_SLOTS
#define VEIL_VOLUME_SLOTS VEIL_MAX_VOLUMES
#endif

layout(binding = VEIL_TEX_VOLUME_DATA) uniform sampler3D volumeData[VEIL_VOLUME_SLOTS];
layout(binding = VEIL_TEX_VOLUME_TABLE) uniform usampler3D volumeTable[VEIL_VOLUME_SLOTS];

const int kLeafSize = 8;
const int kBrickSize = 10;

// Texture coordinate of index-space point p in volume i's data (atlas or dense; the emission
// channel has the same layout). emptyLeaf is set where the leaf holds no brick (or p is
// outside), so the marcher can skip the whole leaf; the coordinate is then meaningless.
vec3 volumeCoord(int i, vec3 p, out bool emptyLeaf) {
    emptyLeaf = false;
    if (any(lessThan(p, volumes[i].indexMin)) || any(greaterThanEqual(p, volumes[i].indexMax))) {
        emptyLeaf = true;
        return vec3(0.0);
    }
    vec3 dims = vec3(textureSize(volumeData[i], 0));
    if (volumes[i].bricksPerAxis.x == 0) return (p - volumes[i].indexMin + 0.5) / dims;
    ivec3 cell = ivec3(floor(p));
    ivec3 leafCoord = cell >> 3; // floor division by 8, also for negative coordinates
    uint b = texelFetch(volumeTable[i], leafCoord - volumes[i].leafOrigin, 0).r;
    if (b == 0u) {
        emptyLeaf = true;
        return vec3(0.0);
    }
    b -= 1u;
    uvec3 bpa = uvec3(volumes[i].bricksPerAxis);
    vec3 slot = vec3(b % bpa.x, (b / bpa.x) % bpa.y, b / (bpa.x * bpa.y));
    vec3 local = p - vec3(leafCoord * kLeafSize) + 1.0; // apron of one voxel
    return (slot * float(kBrickSize) + local + 0.5) / dims;
}

// Unscaled density of volume i at index-space point p (trilinear); emptyLeaf as volumeCoord().
float sampleVolumeIndex(int i, vec3 p, out bool emptyLeaf) {
    vec3 uvw = volumeCoord(i, p, emptyLeaf);
    return emptyLeaf ? 0.0 : texture(volumeData[i], uvw).r;
}

// Henyey-Greenstein phase function; cosTheta between the light's travel direction and the
// direction toward the eye.
float henyeyGreenstein(float cosTheta, float g) {
    float d = 1.0 + g * g - 2.0 * g * cosTheta;
    return (1.0 - g * g) / (4.0 * PI * d * sqrt(d));
}

// Ray parameter interval [t0, t1] of volume i's index-space box [indexMin, indexMax] along the
// world ray ro + t rd (empty when t0 >= t1). An axis the ray runs parallel to is tested
// directly (no 0 * inf = NaN when the origin lies on a face).
vec2 volumeBoxInterval(int i, vec3 ro, vec3 rd) {
    vec3 o = (volumes[i].worldToIndex * vec4(ro, 1.0)).xyz;
    vec3 d = mat3(volumes[i].worldToIndex) * rd;
    float t0 = -1e30, t1 = 1e30;
    for (int k = 0; k < 3; ++k) {
        if (abs(d[k]) < 1e-20) {
            if (o[k] < volumes[i].indexMin[k] || o[k] > volumes[i].indexMax[k])
                return vec2(1e30, -1e30);
        } else {
            float a = (volumes[i].indexMin[k] - o[k]) / d[k];
            float b = (volumes[i].indexMax[k] - o[k]) / d[k];
            t0 = max(t0, min(a, b));
            t1 = min(t1, max(a, b));
        }
    }
    return vec2(t0, t1);
}

// Extinction coefficient at world point w: the sum over the volumes of density_scale x density.
float volumeExtinction(vec3 w) {
    float sigma = 0.0;
    for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i)
        if (i < volumeCount) {
            bool empty;
            vec3 p = (volumes[i].worldToIndex * vec4(w, 1.0)).xyz;
            sigma += volumes[i].densityScale * sampleVolumeIndex(i, p, empty);
        }
    return sigma;
}

// Distance along the ray over which volume i stays empty from world point P, where
// sampleVolumeIndex() calls P's leaf empty: the exit of P's 8^3 leaf (index space of i), or,
// where P is outside the stored bounds, the entry into them (less a thousandth of a voxel for
// rounding), which need not be a leaf boundary: the dense path's bounds are the voxels' box.
float leafExit(int i, vec3 P, vec3 rd) {
    vec3 p = (volumes[i].worldToIndex * vec4(P, 1.0)).xyz;
    vec3 d = mat3(volumes[i].worldToIndex) * rd;
    if (any(lessThan(p, volumes[i].indexMin)) || any(greaterThanEqual(p, volumes[i].indexMax))) {
        float tNear = 0.0, tFar = 1e30;
        for (int k = 0; k < 3; ++k) {
            if (abs(d[k]) > 1e-12) {
                float ta = (volumes[i].indexMin[k] - p[k]) / d[k];
                float tb = (volumes[i].indexMax[k] - p[k]) / d[k];
                tNear = max(tNear, min(ta, tb));
                tFar = min(tFar, max(ta, tb));
            } else if (p[k] < volumes[i].indexMin[k] || p[k] >= volumes[i].indexMax[k]) {
                return 1e30; // parallel to this slab and outside it: never enters
            }
        }
        if (tNear > tFar) return 1e30;
        return max(tNear - 1e-3 / max(length(d), 1e-20), 0.0);
    }
    vec3 leafLo = floor(p / float(kLeafSize)) * float(kLeafSize);
    vec3 bound = mix(leafLo, leafLo + float(kLeafSize), greaterThan(d, vec3(0.0)));
    float tMin = 1e30;
    for (int k = 0; k < 3; ++k)
        if (abs(d[k]) > 1e-12) tMin = min(tMin, (bound[k] - p[k]) / d[k]);
    return max(tMin, 0.0);
}

// Distance along the ray to leave the current leaf of the nearest-exiting volume (where every
// volume's leaf is empty, nothing is sampled before it).
float volumesLeafExit(vec3 P, vec3 rd) {
    float exitT = 1e30;
    for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i)
        if (i < volumeCount) exitT = min(exitT, leafExit(i, P, rd));
    return exitT;
}

// The first index of steps of dt from t0 (sample offset `offset` in [0, 1)) whose sample lies
// at or past t + skip: where a march resumes after empty space. Capped so that the int cannot
// overflow (volumesLeafExit() is 1e30 where the ray meets no more data).
int firstStepPast(float t, float skip, float t0, float dt, float offset) {
    return int(min(ceil((t + skip - t0) / dt - offset), 1e9));
}

// Extinction at w as volumeExtinction(); allEmpty is set where every volume's leaf is empty
// (or w is outside every volume), i.e. the extinction is 0 up to volumesLeafExit().
float volumeExtinctionOrEmpty(vec3 w, out bool allEmpty) {
    float sigma = 0.0;
    allEmpty = true;
    for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i)
        if (i < volumeCount) {
            bool empty;
            vec3 p = (volumes[i].worldToIndex * vec4(w, 1.0)).xyz;
            sigma += volumes[i].densityScale * sampleVolumeIndex(i, p, empty);
            allEmpty = allEmpty && empty;
        }
    return sigma;
}
