// Lookups in the opaque casters' depth array (src/shadows/common/depth_maps.h), shared by
// every shadow technique: each of them also needs the opaque map. params[0].x = bias (world
// units), params[0].y = PCF radius.
#include "../../common/lights.glsl"
#include "views.glsl"

layout(binding = VEIL_TEX_SHADOW_MAP) uniform sampler2DArrayShadow shadowDepthArray;

// The light view that sees P, its map uv, normalized depth and the clip w dividing uv; false =
// P is not shadowed.
bool shadowLocate(int light, vec3 P, out int view, out vec2 uv, out float depth, out float w) {
    view = shadowViewOf(light, P, lighting.lights[light].positionType.xyz);
    return shadowViewCoordinates(view, P, uv, depth, w);
}

bool shadowLocate(int light, vec3 P, out int view, out vec2 uv, out float depth) {
    float w;
    return shadowLocate(light, P, view, uv, depth, w);
}

// Receiver-plane depth slope [Isidoro06]: the normalized depth of the plane through P, per
// texel of offset in view v's map (x, y). Filter taps at offset o compare against
// depth + dot(slope, o) instead of P's own depth, so a flat receiver tilted toward the light
// does not meet itself in its neighbours' texels. Capped at 8 texel widths of depth per texel
// (the slope of a plane 83 degrees from the light's axis, with texels as wide as the view's
// depth range / size).
//
// VEIL_RECEIVER_SLOPE, the technique's receiver_slope, is compiled into every surface
// receiver's program (shadows::Technique::receivers, opaqueMapDefines): 0 = derivatives (the
// default when undefined), 1 = geometric, 2 = none (a zero slope, no code; for measuring its
// cost), 3 = plane-bias (the derivatives' slope sets the bias alone: every tap compares at one
// depth, offset by the plane's largest depth change over the kernel's footprint).
// A fragment shader that defines VEIL_RECEIVER_DERIVATIVES takes its directions from the
// screen-space derivatives (receiver_derivatives.glsl) in modes 0 and 3 and has no geometric
// code; the compute receivers (no derivatives) take the geometric directions in modes 0, 1, 3.
#ifndef VEIL_RECEIVER_SLOPE
#define VEIL_RECEIVER_SLOPE 0
#endif

// The slope of the plane spanned by directions e1, e2 (world space, any length) at the point
// with map coordinates uv = c.xy / c.w, c = T (P, 1), T = worldToTexture, w = c.w. Along e the
// homogeneous coordinates change by m = T (e, 0) (linear part of T: the rows x, y, w, three
// multiply-adds each), so the exact derivative of uv is (m.xy - uv m.w) / w, i.e. size / w
// times a = m.xy - uv m.w in texels; the depth is linear along the view's axis, so its
// derivative is -(V (e, 0)).z / range (V = worldToView, one row). The slope g solves
// g . d_i = z_i for the two map offsets d_i = (size / w) a_i and depth changes z_i; by
// Cramer's rule, with det = a_1 x a_2 (2D cross product),
//   g = (w / size) (z_1 a_2.y - z_2 a_1.y, z_2 a_1.x - z_1 a_2.x) / det,
// where the 1 / range of z and the w / size scale fold into one factor: one reciprocal per
// light, and the lengths of e1, e2 cancel. Zero where a_1, a_2 are within 1e-3 radians of
// parallel (det^2 <= 1e-6 |a_1|^2 |a_2|^2: the plane seen edge-on by the light, or a pixel
// footprint seen edge-on by the camera, or a zero direction); the slope-scaled bias of
// opaqueVisibility covers those grazing receivers.
vec2 shadowPlaneSlope(int v, vec2 uv, float w, vec3 e1, vec3 e2) {
    vec4 m1 = shadows.views[v].worldToTexture * vec4(e1, 0.0);
    vec4 m2 = shadows.views[v].worldToTexture * vec4(e2, 0.0);
    vec2 a1 = m1.xy - uv * m1.w, a2 = m2.xy - uv * m2.w;
    float z1 = (shadows.views[v].worldToView * vec4(e1, 0.0)).z;
    float z2 = (shadows.views[v].worldToView * vec4(e2, 0.0)).z;
    float det = a1.x * a2.y - a1.y * a2.x;
    float s = det * det > 1e-6 * dot(a1, a1) * dot(a2, a2)
                  ? -w * shadows.mapSize.y / (det * shadowViewDepthScale(v))
                  : 0.0;
    vec2 g = vec2(z1 * a2.y - z2 * a1.y, z2 * a1.x - z1 * a2.x) * s;
    float cap = 8.0 * shadows.mapSize.y;
    return clamp(g, vec2(-cap), vec2(cap));
}

#include "receiver_derivatives.glsl"

// The slope at a receiver with normal N whose map coordinates are uv (clip w = w).
// Derivatives: the pixel steps dP/dx, dP/dy of the fragment (the plane of its triangle),
// taken once per fragment before any branch, so every light's slope is shadowPlaneSlope's
// few multiply-adds. Geometric: two tangents of the plane with normal N.
vec2 shadowReceiverSlope(int v, vec3 N, vec2 uv, float w) {
#if VEIL_RECEIVER_SLOPE == 2
    return vec2(0.0);
#elif (VEIL_RECEIVER_SLOPE == 0 || VEIL_RECEIVER_SLOPE == 3) && defined(VEIL_RECEIVER_DERIVATIVES)
    return shadowPlaneSlope(v, uv, w, shadowReceiverDPdx, shadowReceiverDPdy);
#else
    vec3 t1 = cross(N, abs(N.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0));
    return shadowPlaneSlope(v, uv, w, t1, cross(N, t1));
#endif
}

// Surfaces: slope-scaled receiver bias (grows where the light grazes the surface), PCF.
float opaqueVisibility(int light, vec3 P, vec3 N, vec3 L) {
    int v;
    vec2 uv;
    float z, w;
    if (!shadowLocate(light, P, v, uv, z, w)) return 1.0;
    float NdotL = saturate(dot(N, L));
    float bias = shadows.params[0].x * (1.0 + 4.0 * (1.0 - NdotL)) / shadowViewDepthScale(v);
    int r = int(shadows.params[0].y);
    float texel = shadows.mapSize.y;
    // Each tap's hardware comparison filters 2x2 texels: the receiver plane one texel on.
    vec2 slope = shadowReceiverSlope(v, N, uv, w);
    bias += abs(slope.x) + abs(slope.y);
#if VEIL_RECEIVER_SLOPE == 3
    // Plane-bias: the taps r texels out (and their 2x2 footprints) meet the plane up to
    // (r + 1) (|slope.x| + |slope.y|) above P's depth; all of it goes into the one bias.
    bias += float(r) * (abs(slope.x) + abs(slope.y));
    slope = vec2(0.0);
#endif
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
