#version 450 core
// Stencil shadow volumes (src/shadows/volume), one light per draw, triangles with adjacency.
//   mode 0: depth pre-pass of the receivers: the triangle itself.
//   mode 1: closed 2-manifold casters: for a triangle facing the light, the front cap (the
//           triangle), the back cap (the triangle extruded) and one side quad per silhouette
//           edge (the neighbour across the edge does not face the light).
//   mode 2: any other mesh (open, non-manifold): every triangle is its own closed prism (caps
//           and sides, wound to face outward whichever way the triangle faces), exact for a
//           triangle soup. The side on an edge shared with a neighbour of the same facing is
//           left out: the neighbour's side there is the same quad wound the other way, and the
//           pair adds nothing to the count anywhere (it would only add rounding where a
//           receiver lies on the edge). Open and non-manifold edges have the triangle itself
//           as "neighbour" in the adjacency (reversed: the other facing), so they get a side.
// Depth-fail counting (Carmack's reverse; Everitt & Kilgard 2002): back faces behind the
// receiver increment, front faces behind it decrement, so the count is the winding number of
// the receiver in the union of volumes, right with the camera inside a volume. Extrusion is to
// infinity (w = 0) with depth clamping instead of a far plane, or to the clamp depth of the
// caster when 003 Sec. 3.2 clamping gave it one (a plane of constant depth along the light's
// view axis: the volume stays closed).
//
// The pre-pass and the front caps emit the same vertices through the same expression with an
// invariant gl_Position, so a receiver on a lit face and the cap on it have equal depths: the
// cap fails GL_LESS, is counted, and the face is outside its own volume without any bias.
#include "../../common/camera.glsl"
#include "../common/views.glsl"

layout(triangles_adjacency) in;
layout(triangle_strip, max_vertices = 18) out;

in vec3 gWorld[];
flat in int gIndex[];
invariant gl_Position;

uniform int mode;
uniform vec4 lightPos;      // xyz = position (w = 1) or unit direction of travel (w = 0)
uniform int lightView;      // the light's view for clamped extrusion (-1: point light)
uniform int casterSlot;     // index of this caster and light in casterClamp
uniform float finiteExtrude; // > 0: orthographic camera, extrude this far instead of to w = 0

// Per caster and light (classify.comp): < 0 culled, 0 = extrude to infinity, > 0 = clamp at
// this normalized depth of lightView.
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_CASTERS) readonly buffer Casters {
    float casterClamp[];
};

void emitWorld(vec4 p) {
    gl_Position = camera.viewProjection * p;
    EmitVertex();
}

// > 0 where the triangle (a, b, c), counter-clockwise, faces the light. The vertices are
// rotated so that the smallest index comes first: a triangle read as a neighbour and as itself
// gives the same bits, so an edge is a silhouette for exactly one of its two triangles.
float facing(int ia, int ib, int ic) {
    int i0 = ia, i1 = ib, i2 = ic;
    int ka = gIndex[ia], kb = gIndex[ib], kc = gIndex[ic];
    if (kb < ka && kb < kc) {
        i0 = ib;
        i1 = ic;
        i2 = ia;
    } else if (kc < ka && kc < kb) {
        i0 = ic;
        i1 = ia;
        i2 = ib;
    }
    vec3 a = gWorld[i0], b = gWorld[i1], c = gWorld[i2];
    vec3 toLight = lightPos.w > 0.5 ? lightPos.xyz - a : -lightPos.xyz;
    return dot(cross(b - a, c - a), toLight);
}

float clampDepth;

vec4 extrude(vec3 p) {
    if (clampDepth > 0.0) {
        // 003 Sec. 3.2 clamping: the plane at normalized depth clampDepth of the light's view.
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

// Directional light extruded to infinity: every extruded vertex is the same point.
bool degenerateBack() { return lightPos.w < 0.5 && clampDepth == 0.0 && finiteExtrude == 0.0; }

// Side of edge (a -> b) of a light-facing triangle, facing out of the volume.
void side(int a, int b) {
    vec4 ea = extrude(gWorld[a]);
    emitWorld(vec4(gWorld[a], 1.0));
    emitWorld(ea);
    emitWorld(vec4(gWorld[b], 1.0));
    if (!degenerateBack()) emitWorld(extrude(gWorld[b]));
    EndPrimitive();
}

// The volume of light-facing triangle (a, b, c): caps, and the sides where `edge` says so.
void prism(int a, int b, int c, bvec3 edge) {
    emitWorld(vec4(gWorld[a], 1.0));
    emitWorld(vec4(gWorld[b], 1.0));
    emitWorld(vec4(gWorld[c], 1.0));
    EndPrimitive();
    if (!degenerateBack()) {
        emitWorld(extrude(gWorld[a]));
        emitWorld(extrude(gWorld[c]));
        emitWorld(extrude(gWorld[b]));
        EndPrimitive();
    }
    if (edge.x) side(a, b);
    if (edge.y) side(b, c);
    if (edge.z) side(c, a);
}

void main() {
    if (mode == 0) {
        emitWorld(vec4(gWorld[0], 1.0));
        emitWorld(vec4(gWorld[2], 1.0));
        emitWorld(vec4(gWorld[4], 1.0));
        EndPrimitive();
        return;
    }
    clampDepth = casterClamp[casterSlot];
    if (clampDepth < 0.0) return; // culled (003 Sec. 3.2)
    float f = facing(0, 2, 4);
    if (mode == 1) {
        if (f <= 0.0) return;
        prism(0, 2, 4, bvec3(facing(0, 1, 2) <= 0.0, facing(2, 3, 4) <= 0.0,
                             facing(4, 5, 0) <= 0.0));
    } else if (f > 0.0) {
        prism(0, 2, 4, bvec3(facing(0, 1, 2) <= 0.0, facing(2, 3, 4) <= 0.0,
                             facing(4, 5, 0) <= 0.0));
    } else if (f < 0.0) { // faces away: the same prism wound the other way
        prism(0, 4, 2, bvec3(facing(4, 5, 0) >= 0.0, facing(2, 3, 4) >= 0.0,
                             facing(0, 1, 2) >= 0.0));
    }
}
