// OIT technique `phenomenological` [McGuire16, McGuire17]: one unordered pass writes
// each transparent fragment's contribution into three blended targets ([McGuire16 Table 2], with
// the formats changed as noted in src/oit/phenomenological/phenomenological.h):
//   RT0  (A_rgb, A_a)            additive            [McGuire16 Eq. 4] numerator / denominator
//   RT1  (beta_rgb, D^2 / Dmax^2)  rgb: dst *= 1 - src  [McGuire16 Eq. 2]; a: additive (Eq. 7)
//   RT2  sum c_i w_i delta_i / 64    additive          [McGuire16 Eq. 8-9] [McGuire17 Eq. 9-10], averaged
//        (RG16F; only with refraction, define PHEN_REFRACTION)
// where c_i = alpha_i (1 - mean t_i) is the net coverage (Listing 1 `netCoverage`) and w_i the
// Eq. 5 depth weight: the resolve divides RT2 by A_a = sum c_i w_i, so the layers' offsets are
// averaged with the weights of their reflected light (Eq. 4). [McGuire17 sec. 4.3.2] asks for an
// average "weighted by coverage and opacity" without fixing the weights, and its listing sums
// c_i delta_i unnormalized; weighting by c_i w_i instead of c_i needs no weight-sum channel
// (RT2 is two channels, 4 bytes, instead of RGBA16F), and is the same for a single layer and
// for layers of equal weight.
//
// Entry point: oitEmit(OitFragment f) (shaders/oit/fragment.glsl). Surfaces use its
// collimation, eta, view-space position and viewer-facing normal; the fog's contribution
// (f.surface false) is collimated (c = 1) and non-refracting (eta = 1).
// Per-pixel contributions (the fog) come from compute through this oitEmit() (OIT_COMPUTE,
// shaders/oit/fragment.glsl): the three targets are images and OIT_WRITE applies the blend
// equations of the appendix (A += o.A; beta *= 1 - o.betaD.rgb, D^2 += o.betaD.a; delta +=
// o.delta). Only media contributions (f.surface false) may come that way: the surface path
// needs fragment built-ins (gl_FrontFacing for volume refraction). The slice-map pass and the
// low-resolution particle pass take none (PerPixelEmit::None in phenomenological.cpp).
//
// Volume refraction (PhenomenologicalParams::volumeRefraction, defines PHEN_VOLUME): a first
// geometry pass (PHEN_THICKNESS) writes each transparent fragment as one bit of its view-depth
// slice into a front-face and a back-face slice map ([Eisemann06 sec. 3]; 512 slices uniform in view
// depth between the camera's near and far planes, 4 RGBA32UI targets each, OR logic op);
// thickness.comp walks them into a thickness per pixel, which the accumulation pass uses for
// the refraction offset (Delta z := thickness), Beer-Lambert absorption at front faces and a
// thickness x roughness diffusion term (see oitEmit below).
#include "../fragment.glsl"
#include "../../common/camera.glsl"
#include "../../common/math.glsl"

#if defined(PHEN_THICKNESS)
layout(location = 0) out uvec4 phenSliceFront[4]; // slices 0..511, 128 per target
layout(location = 4) out uvec4 phenSliceBack[4];
#else
OIT_TARGET(0, rgba16f, phenOutA);
OIT_TARGET(1, rgba16, phenOutBetaD);
#ifdef PHEN_REFRACTION
OIT_TARGET(2, rg16f, phenOutDelta);
#endif
#endif

#ifdef PHEN_VOLUME
layout(binding = VEIL_PHEN_TEX_THICKNESS) uniform sampler2D phenThickness;
uniform float phenThicknessRef;     // > 0: t := t^(thickness / phenThicknessRef) at front faces
uniform float phenVolumeBlur;       // k_r of the thickness x roughness diffusion term
#endif
// The volume code reads the surface's roughness and attenuation from the OitFragment (the
// fog's contribution has f.surface = false and takes none of it).

// A copy of the opaque depth (the original is attached for the depth test).
layout(binding = VEIL_PHEN_TEX_DEPTH) uniform sampler2D phenOpaqueDepth;

uniform vec2 phenWeightRange;        // [McGuire16 Eq. 5] clamp, (0.01, 30)
uniform float phenK0;                // [McGuire16 Eq. 7] k_0
uniform float phenK1;                // [McGuire16 Eq. 7] k_1
uniform float phenPixelsPerUnit;     // [McGuire16 Eq. 7] W / (2 tan(theta/2)); <= 0: from projection
uniform float phenMaxDiffusionPixels; // [McGuire16 Listing 2]; D^2 is stored divided by its square
uniform float phenRefractionDepth;   // [McGuire16 Eq. 9] Delta z
uniform bool phenDiffusion;
uniform bool phenRefraction;

// Window depth in [0,1] (gl_FragCoord.z) of a point at view distance viewDepth.
float phenWindowDepth(float viewDepth) {
    float z = -viewDepth;
    mat4 P = camera.projection;
    float ndc = (P[2][2] * z + P[3][2]) / (P[2][3] * z + P[3][3]);
    return 0.5 * ndc + 0.5;
}

// View distance (positive) of window depth d: inverts the projection's z row (perspective and
// orthographic alike).
float phenViewDepthFromWindow(float d) {
    mat4 P = camera.projection;
    float ndc = 2.0 * d - 1.0;
    float z = (P[3][2] - ndc * P[3][3]) / (ndc * P[2][3] - P[2][2]);
    return -z;
}

vec2 phenProjectToPixels(vec3 viewPos) {
    vec4 clip = camera.projection * vec4(viewPos, 1.0);
    return (clip.xy / clip.w * 0.5 + 0.5) * camera.viewport.xy;
}

struct PhenOutput {
    vec4 A;
    vec4 betaD;
    vec2 delta;
};

// [McGuire16 Listing 1] (computeOutput). radiance = alpha * L_r. t = transmission. c = collimation.
// eta = relative refractive index eta_before / eta_after ([McGuire16 Eq. 8]; 1 / ior entering a
// medium of index ior from air, ior leaving it).
// X, n: camera-space position and unit normal facing the viewer. zB: view distance of the
// opaque background behind the fragment.
// refractionDepth: Eq. 9 Delta z. extraD: diffusion std-dev in world units added to Eq. 7's
// (volume refraction's thickness x roughness term; 0 otherwise).
PhenOutput phenComputeOutput(vec3 radiance, float alpha, vec3 t, float viewDepth, float c,
                             float eta, vec3 X, vec3 n, float zB, float refractionDepth,
                             float extraD) {
    PhenOutput o;
    float netCoverage = alpha * (1.0 - dot(t, vec3(1.0 / 3.0)));
    // [McGuire16 Eq. 5]: w = clamp([10 (1 - 0.99 f) alpha (1 - mean t)]^3, 0.01, 30)
    float tmp = (1.0 - 0.99 * phenWindowDepth(viewDepth)) * netCoverage * 10.0;
    float w = clamp(tmp * tmp * tmp, phenWeightRange.x, phenWeightRange.y);
    o.A = vec4(radiance, netCoverage) * w; // [McGuire16 Eq. 4]
    // [McGuire16 Eq. 2] factor 1 - alpha + alpha t, blended as dst * (1 - src). (Listing 1 also scales
    // this by 1/3, which would break Eq. 2; not done.)
    vec3 betaSrc = alpha * (vec3(1.0) - t);

    // [McGuire16 Eq. 7], one term of the sum, in pixels: k_0 (1 - c) alpha' (1 - 1 / (1 + dz / k_1))
    // times pixels per unit at this depth (W / (2 tan(theta/2)) / |z| for a perspective camera,
    // constant for an orthographic one). Listing 1 weights by net coverage, as here.
    float D2 = 0.0;
    if (phenDiffusion && (c < 1.0 || extraD > 0.0)) {
        float dz = abs(zB - viewDepth);
        float clipW = camera.projection[2][3] * (-viewDepth) + camera.projection[3][3];
        float ppu = phenPixelsPerUnit > 0.0 ? phenPixelsPerUnit
                                            : 0.5 * camera.viewport.x * camera.projection[0][0];
        float D = netCoverage * (phenK0 * (1.0 - c) * (dz / (phenK1 + dz)) + extraD) * ppu /
                  abs(clipW);
        D2 = D * D / (phenMaxDiffusionPixels * phenMaxDiffusionPixels);
        // [McGuire16] appendix: round non-zero values up so they survive the target's precision.
        if (D2 > 0.0) D2 = max(D2, 4.0 / 65535.0);
    }
    o.betaD = vec4(betaSrc, D2);

    // [McGuire16 Eq. 8-9]: refract the eye ray at X and intersect a plane Delta z behind X; the
    // offset is the projected point minus X's pixel. GLSL refract() is Snell's law for the
    // ray direction ([McGuire16 Eq. 8] as printed has a typo: it does not give a unit vector at
    // normal incidence). k < 0 (total internal reflection): no transmitted transport, no
    // offset.
    vec2 delta = vec2(0.0);
    if (phenRefraction && eta != 1.0 && netCoverage > 0.0) {
        vec3 I = camera.cameraForward.w > 0.5 ? vec3(0.0, 0.0, -1.0) : normalize(X);
        vec3 wi = refract(I, n, eta);
        if (dot(wi, wi) > 0.0) {
            vec3 B = X + wi * (refractionDepth / max(-wi.z, 1e-4));
            delta = phenProjectToPixels(B) - phenProjectToPixels(X);
        }
    }
    // [McGuire17 sec. 4.3.2]: the offsets of all layers are averaged, weighted by c w (the header);
    // / 64 keeps the float16 sum finite up to 64x A_a's range.
    o.delta = delta * (netCoverage * w / 64.0);
    return o;
}

#ifndef OIT_COMPUTE
// Reduced-resolution particles [McGuire16 sec. 3 and 5 "Upsample"]: with two geometry passes,
// pass 0 (full resolution) skips billboard meshes and pass 1 (1/2 or 1/4 resolution) draws only
// them, testing depth by hand against a downsampled key (the farthest opaque depth of the
// block, bound as phenOpaqueDepth) since the low-resolution targets have no depth buffer.
void phenPassFilter(bool billboard) {
#if defined(PHEN_SKIP_BILLBOARDS)
    if (billboard) discard;
#elif defined(PHEN_LOWRES)
    if (!billboard) discard;
    if (gl_FragCoord.z >= texelFetch(phenOpaqueDepth, ivec2(gl_FragCoord.xy), 0).r) discard;
#endif
}
#endif

float phenBackgroundDepth() {
    return phenViewDepthFromWindow(texelFetch(phenOpaqueDepth, oitPixel, 0).r);
}

#if defined(PHEN_THICKNESS)
// Slice-map pass [Eisemann06 sec. 2-3]: one bit at the fragment's view-depth slice, in the front or
// back map by gl_FrontFacing (closed meshes wound counter-clockwise outward). Every output is
// written (zeros elsewhere): the targets are OR-ed (glLogicOp). Fog and particles have no
// surfaces bounding a volume: nothing in the slice maps.
void oitEmit(OitFragment f) {
    if (!f.surface || f.particle) discard;
    float viewDepth = f.viewDepth;
    float near = camera.viewport.z, far = camera.viewport.w;
    int s = clamp(int(floor((viewDepth - near) / (far - near) * 512.0)), 0, 511);
    int word = s >> 5;
    uvec4 bits = uvec4(0u);
    bits[word & 3] = 1u << uint(s & 31);
    for (int k = 0; k < 4; ++k) {
        uvec4 v = k == (word >> 2) ? bits : uvec4(0u);
        phenSliceFront[k] = gl_FrontFacing ? v : uvec4(0u);
        phenSliceBack[k] = gl_FrontFacing ? uvec4(0u) : v;
    }
}

#else
// RT1's blend: rgb (ZERO, ONE_MINUS_SRC_COLOR), alpha (ONE, ONE).
vec4 phenBlendBetaD(vec4 dst, vec4 src) {
    return vec4(dst.rgb * (vec3(1.0) - src.rgb), dst.a + src.a);
}

#ifndef OIT_COMPUTE
#include "inferred_ao.glsl" // fragments only (finite differences, gl_FragCoord)
#endif

void phenWrite(PhenOutput o) {
    OIT_WRITE(phenOutA, o.A, oitBlendAdd);
    OIT_WRITE(phenOutBetaD, o.betaD, phenBlendBetaD);
#ifdef PHEN_REFRACTION
    OIT_WRITE(phenOutDelta, vec4(o.delta, 0.0, 0.0), oitBlendAdd);
#endif
}

void oitEmit(OitFragment f) {
#ifndef OIT_COMPUTE
    phenPassFilter(f.particle);
#endif
    if (!f.surface) {
        // A medium's per-pixel contribution: collimated, no refraction, at its own depth.
        phenWrite(phenComputeOutput(f.radiance, f.alpha, f.transmission, f.viewDepth, 1.0, 1.0,
                                    vec3(0.0), vec3(0.0, 0.0, 1.0), f.viewDepth,
                                    phenRefractionDepth, 0.0));
        return;
    }
#ifndef OIT_COMPUTE
    vec3 radiance = f.radiance;
    // [McGuire17 sec. 6]: the ambient part of the reflected light times the inferred AO.
    if (phenInferredAO && !f.particle)
        radiance -= (1.0 - phenInferAmbientVisibility(f.alpha, f.binaryCoverage, f.viewDepth)) *
                    f.ambient;
    float alpha = f.alpha;
    vec3 transmission = f.transmission;
    float viewDepth = f.viewDepth;
    float collimation = f.collimation, eta = f.eta;
    vec3 viewPos = f.viewPos, viewNormal = f.viewNormal;
    bool billboard = f.particle;
    float refractionDepth = phenRefractionDepth;
    float extraD = 0.0;
    vec3 t = transmission;
#if defined(PHEN_VOLUME)
    // h: thickness of transparent media along this pixel's eye ray (thickness.comp).
    vec2 hn = billboard ? vec2(0.0) : texelFetch(phenThickness, ivec2(gl_FragCoord.xy), 0).rg;
    float h = hn.x;
    // The n front faces along the ray share the path: h / n each (exact for one material).
    float hFront = h / max(hn.y, 1.0);
    // (a) [McGuire16 Eq. 9] with Delta z := h: the ray travels h inside the medium.
    if (eta != 1.0 && !billboard) refractionDepth = h;
    if (gl_FrontFacing && h > 0.0) {
        // (b) Beer-Lambert once per pixel, at the faces entering a medium (back faces keep
        // their own t): glTF KHR_materials_volume T = attenuationColor^(h / distance), or
        // without attenuation, the front face's t taken as that of phenThicknessRef of medium.
        if (f.attenuationDistance > 0.0)
            t *= pow(f.attenuationColor, vec3(hFront / f.attenuationDistance));
        else if (phenThicknessRef > 0.0)
            t = pow(t, vec3(hFront / phenThicknessRef));
        // (c) rough interfaces blur in proportion to the path behind them: sigma = k_r r h / n
        // (world units), added to [McGuire16 Eq. 7]'s k_0 (1 - c) term before the pixel scale.
        extraD = phenVolumeBlur * f.roughness * hFront;
    }
#endif
    phenWrite(phenComputeOutput(radiance, alpha, t, viewDepth, collimation, eta, viewPos,
                                viewNormal, phenDiffusion ? phenBackgroundDepth() : viewDepth,
                                refractionDepth, extraD));
#endif // !OIT_COMPUTE
}
#endif // PHEN_THICKNESS
