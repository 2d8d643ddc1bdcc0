#version 450 core
// The fog marcher (issue: OpenVDB density fields ray-marched as fog). Per pixel of the fog
// target (full, 1/2 or 1/4 resolution) from the eye to the opaque depth: extinction, single
// scattering with Henyey-Greenstein (or multiple scattering by octaves, fog_medium.glsl),
// albedo, emission, an ambient term, and light visibility
// = opaque shadow map x transmittance through the volumes (light_transmittance.comp) x
// homogeneous fog toward point and spot lights (fog_medium.glsl). Each step is integrated
// analytically (constant coefficients over the step), accumulated in registers and written
// once [McGuire17 sec. 7.2]; the frame then hands the result to the OIT technique's oitEmit().
#include "fog_medium.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
// rgb = in-scattered + emitted radiance, a = representative view depth of the fog
layout(binding = VEIL_IMG_FOG_RADIANCE, rgba16f) uniform writeonly image2D fogRadiance;
// rgb = transmittance, a = view depth of the opaque surface behind (for upsampling)
layout(binding = VEIL_IMG_FOG_TRANSMITTANCE, rgba16f) uniform writeonly image2D fogTransmittance;

uniform int resolutionDivisor;
// The fog texels marched by this dispatch, [x0, y0) .. [x1, y1): the whole target, or one tile
// of the viewer's tiled refinement (pass::Context::region).
uniform ivec4 marchRegion;

void main() {
    ivec2 q = ivec2(gl_GlobalInvocationID.xy) + marchRegion.xy;
    ivec2 size = imageSize(fogRadiance);
    if (q.x >= min(size.x, marchRegion.z) || q.y >= min(size.y, marchRegion.w)) return;
    ivec2 full = textureSize(opaqueDepth, 0);
    // Full-resolution pixel at the centre of this fog texel's block.
    ivec2 p = min(q * resolutionDivisor + resolutionDivisor / 2, full - 1);
    FogRay r = fogRay(p);

    vec3 radiance = vec3(0.0);
    float T = 1.0;
    float depthWeight = 0.0, depthSum = 0.0;
    if (r.t0 < r.t1) {
        float dt = (r.t1 - r.t0) / float(steps);
        float offset = jitter ? hash(uvec3(q, seed)) : 0.5;
        vec3 V = -r.rd;
        for (int s = 0; s < steps; ++s) {
            float t = r.t0 + (float(s) + offset) * dt;
            vec3 P = r.ro + r.rd * t;
            float sigma;
            vec3 source;
            if (!fogMedium(P, V, sigma, source)) {
                // Empty-space skipping: jump to the first step past the exit of this leaf.
                s = max(s, fogSkipEmptyLeaf(P, r.rd, t, r.t0, dt, offset) - 1);
                continue;
            }
            if (sigma <= 0.0 && all(equal(source, vec3(0.0)))) continue;
            // Constant coefficients over the step: integral of T(t) (S) dt in closed form.
            float stepT = exp(-sigma * dt);
            float integral = sigma > 1e-8 ? (1.0 - stepT) / sigma : dt;
            radiance += T * source * integral;
            float viewDepth = r.startDepth + t * r.axial;
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
    float fogDepth = depthWeight > 0.0 ? depthSum / depthWeight : r.opaqueViewDepth;
    imageStore(fogRadiance, q, vec4(radiance, fogDepth));
    imageStore(fogTransmittance, q, vec4(vec3(T), r.opaqueViewDepth));
}
