#version 450 core
// Stencil shadow volumes (src/shadows/volume), one light per dispatch, one invocation per
// triangle of the casters that survived culling (compact.comp's work list, [Eisemann06 sec. 3.2]). Each
// appends its volume's triangles to triangles[] (drawn by volume.vert with glDrawArraysIndirect):
//   closed 2-manifold casters: for a triangle facing the light, the front cap (the triangle),
//     the back cap (the triangle extruded) and one side quad per silhouette edge (the
//     neighbour across the edge does not face the light). Clamped [Eisemann06 sec. 3.2] volumes end
//     on a plane of constant depth of the light's view, and there the back cap is a fan from
//     one point F of that plane over the extruded silhouette edges (F, e(b), e(a)) instead of
//     every light-facing triangle extruded: both are chains on the plane bounded by the
//     extruded silhouette loops, so they differ by a closed chain in the plane and every point
//     off the plane has the same winding number (the stencil count) with either.
//   any other mesh (open, non-manifold): every triangle is its own closed prism (caps and
//     sides, wound to face outward whichever way the triangle faces), exact for a triangle
//     soup. The side on an edge shared with a neighbour of the same facing is left out (the
//     neighbour's is the same quad wound the other way). Open and non-manifold edges have the
//     triangle itself as "neighbour" in the adjacency (reversed: the other facing): a side.
// Depth-fail counting (Carmack's reverse; [Everitt02]): back faces behind the
// receiver increment, front faces behind it decrement; right with the eye inside a volume.
// With `zpass`, a caster whose volume cannot hold the eye (the segment from the eye toward
// the light misses its bounds) is counted depth-pass instead (front faces in front of the
// receiver increment, back faces decrement): along every pixel's ray from an eye outside a
// closed volume the front and back crossings are equal in number, so both counts are the same
// integer. Depth clamping is on (no near-plane clipping), so the eye, not the near plane, is
// what must lie outside. Depth-pass needs no front cap (it lies on the caster's lit faces, never
// in front of the depth buffer: same vec4, same depth) and no back cap at infinity (depth
// clamped to 1, never in front either); clamped volumes keep their back cap. Extrusion to
// infinity (w = 0, depth clamping), to the caster's clamp depth, or by finiteExtrude for
// orthographic cameras. Directional lights extruded to infinity have no back cap (every
// extruded vertex is the same point).
#include "draw.glsl"
#include "../../common/camera.glsl"
#include "../common/views.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_WORLD) readonly buffer World {
    vec4 world[];
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_ADJACENCY) readonly buffer Adjacency {
    uint adjacency[]; // 6 world vertex indices per triangle: v0 a01 v1 a12 v2 a20
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_CASTERS) readonly buffer Casters {
    float casterClamp[]; // < 0 culled, 0 infinite, > 0 clamp depth (classify.comp)
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_BOUNDS) readonly buffer Bounds {
    vec4 casterBounds[]; // world lo, hi per caster
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_TRIANGLES) writeonly buffer Triangles {
    vec4 triangles[]; // 3 points per triangle
};
uniform vec4 lightPos;       // xyz = position (w = 1) or unit direction of travel (w = 0)
uniform int lightView;       // the light's view for clamped extrusion (-1: point light)
uniform int slot;
uniform int slotCount;
uniform float finiteExtrude; // > 0: orthographic camera, extrude this far instead of to w = 0
uniform bool zpass;          // depth-pass counting for casters whose volume misses the eye
uniform uint capacity;       // points in triangles[]
uniform float eyeMargin;     // world distance by which the casters' bounds are widened

vec4 P[6];
uint K[6];
float clampDepth;

// > 0 where the triangle (a, b, c), counter-clockwise, faces the light. The vertices are
// rotated so that the smallest index comes first: a triangle read as a neighbour and as itself
// gives the same bits, so an edge is a silhouette for exactly one of its two triangles.
float facing(int ia, int ib, int ic) {
    int i0 = ia, i1 = ib, i2 = ic;
    if (K[ib] < K[ia] && K[ib] < K[ic]) {
        i0 = ib;
        i1 = ic;
        i2 = ia;
    } else if (K[ic] < K[ia] && K[ic] < K[ib]) {
        i0 = ic;
        i1 = ia;
        i2 = ib;
    }
    vec3 a = P[i0].xyz, b = P[i1].xyz, c = P[i2].xyz;
    vec3 toLight = lightPos.w > 0.5 ? lightPos.xyz - a : -lightPos.xyz;
    return dot(cross(b - a, c - a), toLight);
}

vec4 extrude(vec3 p) {
    if (clampDepth > 0.0) {
        // [Eisemann06 sec. 3.2] clamping: the plane at normalized depth clampDepth of the light's view.
        float D = shadows.views[lightView].depthRange.x +
                  clampDepth * shadows.views[lightView].depthRange.z;
        float d = -(shadows.views[lightView].worldToView * vec4(p, 1.0)).z;
        if (lightPos.w > 0.5) return vec4(lightPos.xyz + (p - lightPos.xyz) * (D / d), 1.0);
        return vec4(p + lightPos.xyz * (D - d), 1.0);
    }
    vec3 dir = lightPos.w > 0.5 ? p - lightPos.xyz : lightPos.xyz;
    if (finiteExtrude > 0.0) return vec4(p + normalize(dir) * finiteExtrude, 1.0);
    return vec4(dir, 0.0);
}

uint next; // the next point of triangles[]
void emit(vec4 a, vec4 b, vec4 c) {
    triangles[next] = a;
    triangles[next + 1u] = b;
    triangles[next + 2u] = c;
    next += 3u;
}

// Whether the segment from the eye toward the light (to infinity for a directional light)
// meets the caster's world bounds widened by eyeMargin: its volume may hold the eye.
bool mayHoldEye(int caster) {
    vec3 lo = casterBounds[2 * caster].xyz - eyeMargin;
    vec3 hi = casterBounds[2 * caster + 1].xyz + eyeMargin;
    vec3 o = camera.cameraPosition.xyz;
    vec3 d = lightPos.w > 0.5 ? lightPos.xyz - o : -lightPos.xyz;
    float t0 = 0.0, t1 = lightPos.w > 0.5 ? 1.0 : 1e30;
    for (int k = 0; k < 3; ++k) {
        if (abs(d[k]) < 1e-20) {
            if (o[k] < lo[k] || o[k] > hi[k]) return false;
            continue;
        }
        float a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
        t0 = max(t0, min(a, b));
        t1 = min(t1, max(a, b));
    }
    return t0 <= t1;
}

shared uint sCount, sPass, sBase, sPassBase, sEdges, sFans;

void main() {
    clampDepth = 0.0;
    uint t = gl_GlobalInvocationID.x;
    bool live = t < submitted;
    int a = 0, b = 2, c = 4; // the light-facing winding of the triangle
    bvec3 edge = bvec3(false);
    bool fan = false, back = false, pass = false;
    int caster = 0;
    if (live) {
        int lo = 0, hi = int(survivors) - 1; // the last work entry starting at or before t
        while (lo < hi) {
            int mid = (lo + hi + 1) / 2;
            if (work[mid].y <= t) lo = mid;
            else hi = mid - 1;
        }
        caster = int(work[lo].x);
        CasterRange r = ranges[caster];
        uint tri = r.firstTriangle + (t - work[lo].y);
        for (int j = 0; j < 6; ++j) {
            K[j] = adjacency[6u * tri + uint(j)];
            P[j] = world[K[j]];
        }
        clampDepth = casterClamp[caster * slotCount + slot];
        pass = zpass && finiteExtrude == 0.0 && camera.cameraForward.w < 0.5 &&
               !mayHoldEye(caster);
        float f = facing(0, 2, 4);
        if (r.closed == 1u) {
            live = f > 0.0;
            edge = bvec3(facing(0, 1, 2) <= 0.0, facing(2, 3, 4) <= 0.0, facing(4, 5, 0) <= 0.0);
            fan = clampDepth > 0.0;
        } else if (f > 0.0) {
            edge = bvec3(facing(0, 1, 2) <= 0.0, facing(2, 3, 4) <= 0.0, facing(4, 5, 0) <= 0.0);
        } else if (f < 0.0) { // faces away: the same prism wound the other way
            b = 4;
            c = 2;
            edge = bvec3(facing(4, 5, 0) >= 0.0, facing(2, 3, 4) >= 0.0, facing(0, 1, 2) >= 0.0);
        } else {
            live = false;
        }
    }
    // Directional light extruded to infinity: every extruded vertex is the same point, the
    // back cap and the sides' second triangles are empty.
    bool degenerate = lightPos.w < 0.5 && clampDepth == 0.0 && finiteExtrude == 0.0;
    back = !fan && !degenerate && !(pass && clampDepth == 0.0);
    bool front = !pass;
    uint edges = uint(edge.x) + uint(edge.y) + uint(edge.z);
    uint n = live ? uint(front) + uint(back) + edges * (degenerate ? 1u : 2u) + (fan ? edges : 0u)
                  : 0u;

    if (gl_LocalInvocationIndex == 0u) {
        sCount = 0u;
        sPass = 0u;
        sEdges = 0u;
        sFans = 0u;
    }
    barrier();
    uint local = n == 0u ? 0u : pass ? atomicAdd(sPass, n) : atomicAdd(sCount, n);
    if (live && ranges[caster].closed == 1u && edges > 0u) {
        atomicAdd(sEdges, edges);
        if (fan) atomicAdd(sFans, edges);
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        sBase = sCount > 0u ? atomicAdd(drawCount, 3u * sCount) : 0u;
        // Depth-pass triangles from the end of triangles[] down.
        sPassBase = sPass > 0u ? capacity - atomicAdd(passCount, 3u * sPass) - 3u * sPass : 0u;
        if (sPass > 0u) atomicAdd(passTriangles, sPass);
        if (sEdges > 0u) atomicAdd(silhouetteEdges, sEdges);
        if (sFans > 0u) atomicAdd(fanTriangles, sFans);
    }
    barrier();
    if (n == 0u) return;
    next = (pass ? sPassBase : sBase) + 3u * local;

    int v[3] = int[3](a, b, c);
    vec4 E[3];
    for (int j = 0; j < 3; ++j)
        E[j] = extrude(P[v[j]].xyz);
    if (front) emit(P[a], P[b], P[c]); // front cap: the face's own world points
    if (back) emit(E[0], E[2], E[1]);
    vec4 F = vec4(0.0);
    if (fan) {
        vec3 lo = casterBounds[2 * caster].xyz, hi = casterBounds[2 * caster + 1].xyz;
        F = extrude(0.5 * (lo + hi));
    }
    for (int j = 0; j < 3; ++j) {
        if (!edge[j]) continue;
        int k = (j + 1) % 3; // side of edge v[j] -> v[k], facing out of the volume
        emit(P[v[j]], E[j], P[v[k]]);
        if (!degenerate) emit(P[v[k]], E[j], E[k]);
        if (fan) emit(F, E[k], E[j]);
    }
}
