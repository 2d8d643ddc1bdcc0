// OIT `phenomenological`: inferred ambient occlusion at partial coverage ([McGuire17 sec. 6],
// Listing 2). Transparent fragments never reach the depth buffer, so the frame's screen-space
// AO (VEIL_TEX_AO, src/frame/ambient_occlusion.h) has no value for them; at the filtered edge
// (0 < alpha < 1) of a binary-coverage material (baseMIPisBinary: no transmission, binary base
// coverage) the AO is gathered from neighbouring opaque pixels with a hyperbolic weight in
// camera-space z: along the alpha gradient (toward the opaque alpha = 1 interior) when the
// gradient is not negligible, else in a checkerboard-shifted box. Every other transparent
// fragment gets AO = 1. Needs phenOpaqueDepth and phenViewDepthFromWindow (emit.glsl).
layout(binding = VEIL_TEX_AO) uniform sampler2D phenAmbientVisibility;
uniform bool phenInferredAO; // property inferred_ao, and the frame has an AO buffer

// Listing 2 sampleAO: AO at a pixel offset, times its weight, and the weight.
vec2 phenSampleAO(vec2 offset, float z1) {
    ivec2 C = clamp(ivec2(gl_FragCoord.xy + offset), ivec2(0),
                    textureSize(phenAmbientVisibility, 0) - 1);
    float z2 = phenViewDepthFromWindow(texelFetch(phenOpaqueDepth, C, 0).r);
    float ao = texelFetch(phenAmbientVisibility, C, 0).r;
    float weight = 0.01 / (0.01 + abs(z1 - z2)); // hyperbolic weighting
    return vec2(ao * weight, weight);
}

// Listing 2: the ambient visibility of a fragment of coverage alpha at view distance csZ.
float phenInferAmbientVisibility(float alpha, bool baseMipIsBinary, float csZ) {
    // Finite differences first: every fragment of the quad takes part.
    vec2 gradient = vec2(dFdx(alpha), dFdy(alpha));
    if (!(alpha > 0.0 && alpha < 1.0 && baseMipIsBinary)) return 1.0; // other transparents
    float L = length(gradient);
    vec2 sum = vec2(0.0);
    if (L < 1e-4) { // sample a square
        const int R = 3;
        const float stride = 2.0;
        for (int dy = -R; dy <= R; ++dy) {
            float dxShift = float(abs(dy) & 1) - 0.5;
            for (int dx = -R; dx <= R; ++dx)
                sum += phenSampleAO(vec2(float(dx) + dxShift, float(dy)) * stride, csZ);
        }
    } else { // sample a line
        vec2 dir = gradient / L;
        const int R = 12;
        const float stride = 3.0;
        for (int t = 0; t < R; ++t)
            sum += phenSampleAO(dir * (float(t) * stride), csZ);
    }
    return clamp(sum.x / max(0.01, sum.y), 0.0, 1.0);
}
