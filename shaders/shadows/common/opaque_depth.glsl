// Lookups in the opaque casters' depth array (src/shadows/common/depth_maps.h), shared by
// every shadow technique: each of them also needs the opaque map. params[0].x = bias (world
// units), params[0].y = PCF radius.
#include "../../common/lights.glsl"
#include "views.glsl"

layout(binding = VEIL_TEX_SHADOW_MAP) uniform sampler2DArrayShadow shadowDepthArray;

// The light view that sees P, its map uv and normalized depth; false = P is not shadowed.
bool shadowLocate(int light, vec3 P, out int view, out vec2 uv, out float depth) {
    view = shadowViewOf(light, P, lighting.lights[light].positionType.xyz);
    return shadowViewCoordinates(view, P, uv, depth);
}

// Receiver-plane depth slope [Isidoro06]: the normalized depth of the plane through P, per
// texel of offset in view v's map (x, y). Filter taps at offset o compare against
// depth + dot(slope, o) instead of P's own depth, so a flat receiver tilted toward the light
// does not meet itself in its neighbours' texels. With two directions a, b in the plane, their
// map offsets d_a, d_b (texels) and depth changes z_a, z_b give the slope g by solving
// g . d_a = z_a, g . d_b = z_b (a 2x2 system). Capped at 8 texel widths of depth per texel
// (the slope of a plane 83 degrees from the light's axis, with texels as wide as the view's
// depth range / size). shadows.mapSize.w picks the directions (the technique's
// receiver_slope): 0 = the screen-space derivatives of P where the receiver has them
// (fragment shaders, receiver_derivatives.glsl), else the geometric directions; 1 = geometric
// everywhere; 2 = no slope (comparisons of its cost).

vec2 shadowSlopeSolve(vec2 d1, vec2 d2, float z1, float z2, float det) {
    vec2 g = vec2(z1 * d2.y - z2 * d1.y, z2 * d1.x - z1 * d2.x) / det;
    float cap = 8.0 * shadows.mapSize.y;
    return clamp(g, vec2(-cap), vec2(cap));
}

// Geometric directions: two tangents of the plane with normal N, a thousandth of the view's
// depth range long, projected into the map (two more projections and depths per light).
// Zero where the plane is seen edge-on by the light.
vec2 shadowReceiverSlopeGeometric(int v, vec3 P, vec3 N, vec2 uv, float depth) {
    vec3 a = abs(N.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 t1 = normalize(cross(N, a)), t2 = cross(N, t1);
    float h = 1e-3 * shadowViewDepthScale(v);
    vec4 c1 = shadows.views[v].worldToTexture * vec4(P + t1 * h, 1.0);
    vec4 c2 = shadows.views[v].worldToTexture * vec4(P + t2 * h, 1.0);
    if (c1.w <= 0.0 || c2.w <= 0.0) return vec2(0.0);
    vec2 d1 = (c1.xy / c1.w - uv) * shadows.mapSize.x, d2 = (c2.xy / c2.w - uv) * shadows.mapSize.x;
    float det = d1.x * d2.y - d1.y * d2.x;
    if (abs(det) < 1e-8) return vec2(0.0);
    float z1 = shadowViewDepth(v, P + t1 * h) - depth;
    float z2 = shadowViewDepth(v, P + t2 * h) - depth;
    return shadowSlopeSolve(d1, d2, z1, z2, det);
}

#include "receiver_derivatives.glsl"

// Screen-space directions: the pixel steps dP/dx, dP/dy of the fragment (the plane of its
// triangle), carried into the map by the derivative of the view's projection at P (exact for
// a directional light's orthographic view), so d(uv, z)/dx and /dy of the shadow
// coordinates cost a few multiply-adds per light and need no derivative inside the lights'
// divergent branches. False where the two map offsets are within 1e-3 radians of parallel
// (the pixel's footprint seen edge-on by the light or the camera): the caller takes the
// geometric slope there.
bool shadowReceiverSlopeDerivatives(int v, vec3 P, vec2 uv, out vec2 slope) {
    slope = vec2(0.0);
    float w = (shadows.views[v].worldToTexture * vec4(P, 1.0)).w;
    vec4 cx = shadows.views[v].worldToTexture * vec4(shadowReceiverDPdx, 0.0);
    vec4 cy = shadows.views[v].worldToTexture * vec4(shadowReceiverDPdy, 0.0);
    float s = shadows.mapSize.x / w;
    vec2 d1 = (cx.xy - uv * cx.w) * s, d2 = (cy.xy - uv * cy.w) * s;
    float det = d1.x * d2.y - d1.y * d2.x;
    if (!(det * det > 1e-6 * dot(d1, d1) * dot(d2, d2))) return false;
    float zs = -1.0 / shadowViewDepthScale(v);
    float z1 = (shadows.views[v].worldToView * vec4(shadowReceiverDPdx, 0.0)).z * zs;
    float z2 = (shadows.views[v].worldToView * vec4(shadowReceiverDPdy, 0.0)).z * zs;
    slope = shadowSlopeSolve(d1, d2, z1, z2, det);
    return true;
}

vec2 shadowReceiverSlope(int v, vec3 P, vec3 N, vec2 uv, float depth) {
    int mode = int(shadows.mapSize.w);
    if (mode == 2) return vec2(0.0);
#ifdef VEIL_RECEIVER_DERIVATIVES
    vec2 slope;
    if (mode == 0 && shadowReceiverSlopeDerivatives(v, P, uv, slope)) return slope;
#endif
    return shadowReceiverSlopeGeometric(v, P, N, uv, depth);
}

// Surfaces: slope-scaled receiver bias (grows where the light grazes the surface), PCF.
float opaqueVisibility(int light, vec3 P, vec3 N, vec3 L) {
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(light, P, v, uv, z)) return 1.0;
    float NdotL = saturate(dot(N, L));
    float bias = shadows.params[0].x * (1.0 + 4.0 * (1.0 - NdotL)) / shadowViewDepthScale(v);
    int r = int(shadows.params[0].y);
    float texel = shadows.mapSize.y;
    // Each tap's hardware comparison filters 2x2 texels: the receiver plane one texel on.
    vec2 slope = shadowReceiverSlope(v, P, N, uv, z);
    bias += abs(slope.x) + abs(slope.y);
    float sum = 0.0;
    for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x)
            sum += texture(shadowDepthArray, vec4(uv + vec2(x, y) * texel, float(v),
                                                  z + dot(slope, vec2(x, y)) - bias));
    float n = float(2 * r + 1);
    return sum / (n * n);
}

// Volume samples: one hardware-filtered tap (bilinear 2x2 comparison); the fog marcher takes
// many samples per pixel, so per-sample PCF kernels are not worth their cost.
float opaqueVisibilityFast(int light, vec3 P) {
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(light, P, v, uv, z)) return 1.0;
    return texture(shadowDepthArray,
                   vec4(uv, float(v), z - shadows.params[0].x / shadowViewDepthScale(v)));
}
