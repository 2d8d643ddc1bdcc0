// "veil:light_visibility" of the `stochastic-vsm` shadow technique (src/shadows/stochastic):
// the opaque casters' Williams map (opaque_depth.glsl) times the variance shadow map of the
// caustic colored stochastic shadow map (000 sec. 4.3), per channel: one bilinear tap of the
// blurred moments (E[z], E[z^2]) and Chebyshev's one-sided bound
//     p = sigma^2 / (sigma^2 + (z - mu)^2)  for z > mu, else 1
// (Donnelly and Lauritzen 2006), with the light-bleeding reduction linstep(amount, 1, p).
// The map holds the opaque casters too, so for a receiver behind one transparent plane of
// density rho the texel's samples are {plane: rho, receiver: 1 - rho} and p = 1 - rho exactly.
// No depth bias: the variance floor sigma_min = bias / depth scale (the opaque map's world
// bias in map units) absorbs the receiver's own depth and its slope within a texel.
//
// params[0]: opaque map (bias, PCF radius). params[1]: x = light-bleeding amount, y = layers
// per view L (3: one map per channel, layer v L + c; 1: grey).
#include "../common/opaque_depth.glsl"

layout(binding = VEIL_TEX_SHADOW1) uniform sampler2DArray vsmMap;

float vsmChebyshev(vec2 m, float z, float minVariance, float bleeding) {
    if (z <= m.x) return 1.0;
    float variance = max(m.y - m.x * m.x, minVariance);
    float d = z - m.x;
    float p = variance / (variance + d * d);
    return clamp((p - bleeding) / (1.0 - bleeding), 0.0, 1.0); // linstep(bleeding, 1, p)
}

vec3 vsmVisibility(int i, vec3 P) {
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(i, P, v, uv, z)) return vec3(1.0);
    int L = int(shadows.params[1].y);
    float sigma = shadows.params[0].x / shadowViewDepthScale(v);
    vec3 vis;
    for (int c = 0; c < L; ++c)
        vis[c] = vsmChebyshev(texture(vsmMap, vec3(uv, float(v * L + c))).rg, z, sigma * sigma,
                              shadows.params[1].x);
    return L == 1 ? vec3(vis.x) : vis;
}

void lightAttenuate(int i, vec3 P, vec3 N, vec3 L, inout vec3 radiance) {
    if (shadowLightHasMap(i)) radiance *= opaqueVisibility(i, P, N, L) * vsmVisibility(i, P);
}

void lightAttenuateInMedium(int i, vec3 P, inout vec3 radiance) {
    if (shadowLightHasMap(i)) radiance *= opaqueVisibilityFast(i, P) * vsmVisibility(i, P);
}

vec3 lightVisibility(int i, vec3 P, vec3 N, vec3 L) {
    vec3 v = vec3(1.0);
    lightAttenuate(i, P, N, L, v);
    return v;
}

vec3 lightVisibilityInMedium(int i, vec3 P) {
    vec3 v = vec3(1.0);
    lightAttenuateInMedium(i, P, v);
    return v;
}
