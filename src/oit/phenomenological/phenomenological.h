// OIT technique `phenomenological`: McGuire & Mara, "A Phenomenological Scattering Model for
// Order-Independent Transparency" [McGuire16] and its journal version [McGuire17],
// transparency part: colored transmission beta [McGuire16 Eq. 2], depth-weighted reflected light A
// (Eq. 4-5), diffusion D (Eq. 7) and refraction offset delta (Eq. 8-9) accumulated in one
// unordered pass, then a compute resolve with refraction, occlusion-aware diffusion and
// self-modulation ([McGuire16 sec. 5, Listing 2]; [McGuire17 Eq. 14]).
//
// Parameters (PhenomenologicalParams; defaults in brackets; the properties of the three ids
// are the same names in snake_case, declared in registerPhenomenological):
//   pixelsPerUnit       [0]     Eq. 7's W / (2 tan(theta/2)) ("PPD" of Listing 2, which
//                               uses 200). 0 = from the camera's projection (perspective:
//                               divided by |z| per Eq. 7; orthographic: pixels per world unit).
//   maxDiffusionPixels  [16]    Listing 2 kernel radius clamp. D^2 is stored divided by its
//                               square, so D saturates there (1..64).
//   k0                  [120/63] Eq. 6-7 std-dev (world units) of one c = 0 surface at unit
//                               depth (Listing 1's constant).
//   k1                  [0.5]   Eq. 7 implied thickness of the scattering surface (text: 0.5 m;
//                               Listing 1 uses 0.05).
//   weightMin, weightMax [0.01, 30]  Eq. 5 clamp of the depth weight w.
//   refractionDepth     [2]     Eq. 9 Delta z: background plane distance behind the surface.
//   selfModulation      [on]    [McGuire16 Eq. 13] / [McGuire17 Eq. 14].
//   refraction          [on]    [McGuire16 sec. 5 "Refract"].
//   diffusion           [on]    [McGuire16 sec. 5 "Diffuse"].
//   particleDownsample  [1]     2 or 4: billboard (particle) meshes accumulate at 1/2 or 1/4
//                               resolution and are joint-bilateral upsampled [McGuire16 sec. 5].
//   volumeRefraction    [off]   replaces [McGuire16]'s fixed-distance assumption (section 3) by the
//                               per-pixel thickness h of the transparent geometry, from
//                               front/back slice maps ([Eisemann06 sec. 3]; technique name
//                               `phenomenological-volume`). One extra geometry pass (the first)
//                               and a compute walk (thickness.comp); then in the accumulation:
//                               Eq. 9 Delta z := h for eta != 1 (refractionDepth unused there),
//                               Beer-Lambert at each of the n front faces along the pixel:
//                               t *= attenuationColor^(h / (n d_att))
//                               (glTF KHR_materials_volume, material attenuation_color/_distance)
//                               or, without it, t := t^(h / (n thicknessReference)), and the Eq. 7
//                               std-dev gains volumeBlur * roughness * h (world units).
//   thicknessReference  [0]     medium thickness a surface's transmission t stands for; 0 =
//                               t is not rescaled (only attenuation_distance absorbs).
//   volumeBlur          [0.25]  k_r of the thickness x roughness diffusion term.
//   inferredAO          [on]    [McGuire17 sec. 6 / Listing 2]: at the partial-coverage edge of a
//                               binary-coverage material (scene::Material::baseCoverageIsBinary)
//                               the ambient term is multiplied by AO inferred from the frame's
//                               AO buffer (only when render.ao is enabled; inferred_ao.glsl).
//
// Framebuffer ([McGuire16 Table 2] with changed formats):
//   RT0 A          RGBA16F    as the paper.
//   RT1 beta, D^2  RGBA16 UNORM instead of RGBA8: 8 bits give 1/255 steps in beta, far from the
//                  "exactly matches sorted two-pass" claim of [McGuire16 Fig. 2] (tested to 1e-3).
//                  Alpha holds D^2 / maxDiffusionPixels^2 (Table 2: D^2 / 63^2); without
//                  diffusion it is write-masked (stays 0) and the opaque depth is not copied.
//   RT2 delta      RG16F sum c_i w_i delta_i / 64 (pixels) instead of RG8_SNORM delta / 63,
//                  only with refraction: the resolve divides by RT0's A_a = sum c_i w_i, so the
//                  layers' offsets are averaged [McGuire17 sec. 4.3.2] with the weights of their
//                  reflected light (emit.glsl's header says why not by c_i alone).
// 20 bytes per transparent fragment blended (16 without refraction) plus, per pixel, a depth
// copy (4) and a background copy (8); before 2026-12-01 RT2 was RGBA16F (24 bytes).
// volumeRefraction adds 8 RGBA32UI slice targets (128) and an RG32F thickness, count (8).
//
// Not implemented: caustic stochastic shadow maps (Eq. 10-12). The fog's per-pixel
// contribution comes from compute (PerPixelEmit::Compute in the full-resolution pass;
// emit.glsl's header).
#pragma once

#include "oit/technique.h"

namespace veil::oit {

struct PhenomenologicalParams {
    float pixelsPerUnit = 0.0f;
    int maxDiffusionPixels = 16;
    float k0 = 120.0f / 63.0f;
    float k1 = 0.5f;
    float weightMin = 0.01f;
    float weightMax = 30.0f;
    float refractionDepth = 2.0f;
    bool selfModulation = true;
    bool refraction = true;
    bool diffusion = true;
    int particleDownsample = 1;
    bool volumeRefraction = false;
    float thicknessReference = 0.0f;
    float volumeBlur = 0.25f;
    bool inferredAO = true;

    // Throws veil::Error naming the bad parameter.
    void validate() const;
};

// The same parameters as the technique's property values (snake_case keys: pixels_per_unit,
// max_diffusion_pixels, ...), for render.oit in a scene or RendererOptions::oitProperties.
nlohmann::json toProperties(const PhenomenologicalParams& params);
PhenomenologicalParams phenomenologicalParams(const Properties& properties);

void registerPhenomenological(Registry& registry);

} // namespace veil::oit
