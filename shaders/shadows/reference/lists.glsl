// Per-texel fragment lists of the `reference` shadow technique (src/shadows/reference): every
// transparent caster fragment of every light view, as a node of a pool linked from a head
// image per layer. The product of transmittances is order-independent, so the receiver needs
// no sorting (unlike the OIT reference, which composites radiance): the transmittance in front
// of depth z is the product over the texel's nodes with depth < z.
struct ShadowNode {
    vec4 transmittanceDepth; // rgb = 1 - alpha + alpha T [McGuire16 Eq. 2], a = normalized depth
    uint next;
};
const uint kShadowListEnd = 0xFFFFFFFFu;

layout(std430, binding = VEIL_SSBO_SHADOW_NODES) buffer ShadowNodes { ShadowNode shadowNodes[]; };
layout(std430, binding = VEIL_SSBO_SHADOW_COUNTER) buffer ShadowCounter {
    uint shadowNodeCount;    // nodes asked for (may exceed the capacity: the pass is redone)
    uint shadowNodeCapacity;
};
