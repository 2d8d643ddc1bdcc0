// The shadowed lights' views (src/shadows/views.h fills the block): every shadow-casting light
// has one view (directional: orthographic, spot: perspective) or six (point: the faces of a
// cube, each a perspective view of a little over 90 degrees so that filter kernels near an
// edge stay inside the face). Views are the layers of the shadow technique's texture arrays.
// A map stores the linear depth along the view's axis, normalized to the view's [near, far]
// (uniform precision; biases are in world units).
#include "../../common/bindings.h"

struct ShadowView {
    mat4 worldToTexture; // light view projection followed by [-1,1] -> [0,1]
    mat4 worldToView; // light view (depth along the axis = -z)
    vec4 depthRange;  // near, far, far - near, 1 = orthographic
};

layout(std140, binding = VEIL_UBO_SHADOWS) uniform ShadowsBlock {
    ShadowView views[VEIL_MAX_SHADOW_VIEWS];
    // Per scene light: x = first view (layer) or -1 when the light casts no shadow, y = number of
    // views (1 or 6); z, w unused.
    ivec4 lights[VEIL_MAX_LIGHTS];
    vec4 mapSize; // x = texels per side, y = 1 / x, z = number of views, w unused
    vec4 params[4]; // technique-defined (see the technique's visibility.glsl)
} shadows;

bool shadowLightHasMap(int light) { return shadows.lights[light].x >= 0; }

// Normalized linear depth of P in view v (0 at its near plane, 1 at its far plane).
float shadowViewDepth(int v, vec3 P) {
    float d = -(shadows.views[v].worldToView * vec4(P, 1.0)).z;
    return (d - shadows.views[v].depthRange.x) / shadows.views[v].depthRange.z;
}

// World units per unit of normalized depth in view v (turns world-space biases into map units).
float shadowViewDepthScale(int v) { return shadows.views[v].depthRange.z; }

// The view of `light` that sees P: the light's only view, or for a point light the cube face
// of the dominant axis of P - light position (face order +x, -x, +y, -y, +z, -z).
int shadowViewOf(int light, vec3 P, vec3 lightPosition) {
    ivec4 l = shadows.lights[light];
    if (l.y == 1) return l.x;
    vec3 d = P - lightPosition;
    vec3 a = abs(d);
    int face = a.x >= a.y && a.x >= a.z ? (d.x >= 0.0 ? 0 : 1)
             : a.y >= a.z               ? (d.y >= 0.0 ? 2 : 3)
                                        : (d.z >= 0.0 ? 4 : 5);
    return l.x + face;
}

// Map coordinates of P in view v: texture uv in [0,1]^2, normalized linear depth and the clip
// w that divides uv (1 for an orthographic view; the receiver-plane slope reuses it). False
// where P is outside the view (not shadowed by this map).
bool shadowViewCoordinates(int v, vec3 P, out vec2 uv, out float depth, out float w) {
    vec4 c = shadows.views[v].worldToTexture * vec4(P, 1.0);
    w = c.w;
    if (c.w <= 0.0) return false;
    uv = c.xy / c.w;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return false;
    depth = shadowViewDepth(v, P);
    return depth <= 1.0;
}

bool shadowViewCoordinates(int v, vec3 P, out vec2 uv, out float depth) {
    float w;
    return shadowViewCoordinates(v, P, uv, depth, w);
}
