#version 450 core
// The fog marcher for OIT techniques that keep every surface of a pixel (`reference`,
// Technique::fogSegments()): per full-resolution pixel, after the transparent surfaces are
// stored, the fog between consecutive surfaces (eye -> first surface -> ... -> opaque) is
// integrated piecewise and handed to oitEmit() as one contribution per non-empty segment,
// at a depth inside its segment, so the technique's sort interleaves fog and surfaces
// exactly instead of placing all the fog at one representative depth.
// The quadrature is fog_march.comp's (constant coefficients over a step, closed-form
// integral), with a step that straddles a surface split at the surface.
#define OIT_FOG_SEGMENTS
#define OIT_PIXEL_COORD fogPixel
ivec2 fogPixel;
#include "fog_medium.glsl"
#include "veil:oit_emit"

layout(local_size_x = 8, local_size_y = 8) in;

uniform ivec2 targetSize;
// The pixels marched, [x0, y0) .. [x1, y1): the whole frame or one refinement tile.
uniform ivec4 marchRegion;

// The segment being accumulated: radiance arriving at its front end, its transmittance.
vec3 segL = vec3(0.0);
float segT = 1.0;
float segFrontDepth; // view depth of the surface (or the near plane) in front of the segment
float rayT = 1.0;    // transmittance through the fog so far (all segments)

void addPiece(float sigma, vec3 source, float h) {
    if (h <= 0.0) return;
    float stepT = exp(-sigma * h);
    float integral = sigma > 1e-8 ? (1.0 - stepT) / sigma : h;
    segL += segT * source * integral;
    segT *= stepT;
    rayT *= stepT;
}

// Ends the segment at view depth backDepth: a contribution at the middle of the segment
// (strictly between the surfaces that bound it), then a new empty segment starts there.
void flushSegment(float backDepth) {
    if (segT < 1.0 || any(greaterThan(segL, vec3(0.0))))
        oitEmit(oitFragment(segL, 1.0, vec3(segT), 0.5 * (segFrontDepth + backDepth)));
    segL = vec3(0.0);
    segT = 1.0;
    segFrontDepth = backDepth;
}

void main() {
    // The invocation is the pixel, with no offset: the dispatch starts at pixel 0 and the
    // pixels outside the region return here. Adding the region's origin to the invocation id
    // instead made this march 1.1 ms slower on the H200 (fog.json, 1920x1080, `reference`'s
    // transparent pass 7.41 -> 8.53 ms with the origin at 0; bench/RESULTS.md 2026-12-02).
    fogPixel = ivec2(gl_GlobalInvocationID.xy);
    if (fogPixel.x >= targetSize.x || fogPixel.y >= targetSize.y) return;
    if (any(lessThan(fogPixel, marchRegion.xy)) || any(greaterThanEqual(fogPixel, marchRegion.zw)))
        return;
    FogRay r = fogRay(fogPixel);
    if (!(r.t0 < r.t1)) return;
    uint list = oitSurfaceList(fogPixel);
    float nextSurface = oitNextSurfaceDepth(list, -1e30); // view depth, 1e30: none left
    segFrontDepth = r.startDepth;

    float dt = (r.t1 - r.t0) / float(steps);
    float offset = jitter ? hash(uvec3(fogPixel, seed)) : 0.5;
    vec3 V = -r.rd;
    for (int s = 0; s < steps; ++s) {
        float t = r.t0 + (float(s) + offset) * dt;
        vec3 P = r.ro + r.rd * t;
        float sigma;
        vec3 source;
        if (!fogMedium(P, V, sigma, source)) {
            s = max(s, fogSkipEmptyLeaf(P, r.rd, t, r.t0, dt, offset) - 1);
            continue;
        }
        if (sigma <= 0.0 && all(equal(source, vec3(0.0)))) continue;
        // The step covers [ta, ta + dt]; surfaces inside it split it.
        float ta = r.t0 + float(s) * dt, tb = ta + dt, a = ta;
        while (nextSurface < 1e30) {
            float tk = (nextSurface - r.startDepth) / r.axial;
            if (tk >= tb) break;
            float b = max(tk, a);
            addPiece(sigma, source, b - a);
            flushSegment(nextSurface);
            a = b;
            nextSurface = oitNextSurfaceDepth(list, nextSurface);
        }
        addPiece(sigma, source, tb - a);
        if (rayT < 1e-4) break; // the rest is invisible whatever lies behind
    }
    flushSegment(nextSurface < 1e30 ? nextSurface : r.opaqueViewDepth);
}
