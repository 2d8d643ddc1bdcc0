// The scattered-light cache's textures (render.fog_scattered_light, src/fog/scattered_light_cache.h)
// for the fog marcher (VEIL_SCATTERED_LIGHT, fog_medium.glsl) and the surfaces lit by the cache
// (VEIL_SURFACE_SCATTERED_LIGHT, frame/shading.glsl): over the world box [scatteredLo,
// scatteredHi], the mean radiance arriving after at least one scattering event, from the sky or
// emitted by a volume (rgb, a: luminance) and its P1 flux G (xyz), L(w) ~ mean + G . w for light
// travelling along w (integrators/path_tracer.h ScatteredLight). Declared once whichever of the
// two includes it first.
#if defined(VEIL_SCATTERED_LIGHT) || defined(VEIL_SURFACE_SCATTERED_LIGHT)
#ifndef VEIL_SCATTERED_LIGHT_TEXTURES
#define VEIL_SCATTERED_LIGHT_TEXTURES 1
layout(binding = VEIL_TEX_SCATTERED_LIGHT) uniform sampler3D scatteredMean;
layout(binding = VEIL_TEX_SCATTERED_LIGHT + 1) uniform sampler3D scatteredFlux;
uniform vec3 scatteredLo, scatteredHi;
#endif
#endif

#ifdef VEIL_SURFACE_SCATTERED_LIGHT
// Directions of the rays toward the cache from a surface outside its box.
const int kScatteredSurfaceRays = 32;

// The cache's P1 radiance at world point Q arriving from direction d (travelling along -d):
// mean - G . d, per channel with G's luminance scaled by the channel's mean.
vec3 scatteredRadianceFrom(vec3 Q, vec3 d) {
    vec3 uvw = (Q - scatteredLo) / (scatteredHi - scatteredLo);
    vec4 m = texture(scatteredMean, uvw);
    if (m.a <= 0.0) return m.rgb;
    return m.rgb * max(0.0, 1.0 - dot(texture(scatteredFlux, uvw).xyz, d) / m.a);
}

// What the cache adds to the ambient term's radiance on a surface with normal N at P: E / pi -
// ambient, E its irradiance from the cache (the cache holds the sky seen through the volumes,
// so it replaces the uniform ambient term where it reaches).
//
// Inside the box, the P1 radiance convolved with the clamped cosine [Ramamoorthi01]:
// E(N) = A0 L00 Y00 + A1 sum_m L1m Y1m(N), A0 = pi, A1 = 2 pi / 3. With the cache's terms
// (L(d) = mean - G . d for light arriving from direction d, so L00 Y00 = mean and
// sum_m L1m Y1m(N) = -G . N) this is E / pi = mean (1 - (2/3) G . N / mean_Y), clamped at 0
// (P1 goes negative behind a strongly directional source).
//
// Outside the box (a floor under a fire is usually just below its bounds): radiance does not
// change along a ray through empty space, so the light arriving from direction d is the
// radiance the box sends out where the ray from P along d enters it; a ray that misses the box
// sees the sky. E / pi is the mean over kScatteredSurfaceRays fixed cosine-distributed
// directions about N of the cache's P1 radiance at each ray's entry point toward P.
vec3 scatteredSurfaceLight(vec3 P, vec3 N, vec3 ambient) {
    vec3 lo = scatteredLo, hi = scatteredHi;
    if (all(greaterThanEqual(P, lo)) && all(lessThanEqual(P, hi))) {
        vec3 uvw = (P - lo) / (hi - lo);
        vec4 m = texture(scatteredMean, uvw);
        vec3 g = texture(scatteredFlux, uvw).xyz;
        float e = m.a > 0.0 ? max(0.0, 1.0 - (2.0 / 3.0) * dot(g, N) / m.a) : 1.0;
        return m.rgb * e - ambient;
    }
    // An orthonormal basis about N (Duff et al.'s branchless construction, as the path tracer).
    float s = N.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + N.z), b = N.x * N.y * a;
    vec3 T = vec3(1.0 + s * N.x * N.x * a, s * b, -s * N.x);
    vec3 B = vec3(b, s + N.y * N.y * a, -N.y);
    vec3 sum = vec3(0.0);
    for (int i = 0; i < kScatteredSurfaceRays; ++i) {
        // Cosine-distributed (Malley): stratified radius, golden-angle azimuth.
        float u = (float(i) + 0.5) / float(kScatteredSurfaceRays);
        float r = sqrt(u), phi = 2.39996323 * float(i);
        vec3 d = r * cos(phi) * T + r * sin(phi) * B + sqrt(1.0 - u) * N;
        // The ray against the box (slabs).
        vec3 inv = 1.0 / d;
        vec3 t0 = (lo - P) * inv, t1 = (hi - P) * inv;
        vec3 tmin = min(t0, t1), tmax = max(t0, t1);
        float tNear = max(max(tmin.x, tmin.y), tmin.z);
        float tFar = min(min(tmax.x, tmax.y), tmax.z);
        sum += tNear <= tFar && tFar > 0.0 ? scatteredRadianceFrom(P + max(tNear, 0.0) * d, d)
                                           : ambient;
    }
    return sum / float(kScatteredSurfaceRays) - ambient;
}
#endif
