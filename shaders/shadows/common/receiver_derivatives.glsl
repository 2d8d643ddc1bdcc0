// Screen-space derivatives of the shaded point, for the receiver-plane depth slope of the
// opaque map (opaque_depth.glsl, shadowReceiverSlope, [Isidoro06]). A fragment-shader
// receiver defines VEIL_RECEIVER_DERIVATIVES and calls shadowReceiverDerivatives(P) first
// thing in main(): derivatives are undefined in non-uniform control flow, so they are taken
// before any discard, early return or branch over the lights, once per fragment, and every
// light view's slope follows from them by the chain rule. Compute-shader receivers (the
// compute rasterizer, the fog marcher) have no derivatives: their slope is the geometric one.
// With receiver_slope geometric or none (VEIL_RECEIVER_SLOPE 1 or 2) nothing reads these and
// the compiler drops them.
vec3 shadowReceiverDPdx = vec3(0.0), shadowReceiverDPdy = vec3(0.0);

#ifdef VEIL_RECEIVER_DERIVATIVES
void shadowReceiverDerivatives(vec3 P) {
    shadowReceiverDPdx = dFdx(P);
    shadowReceiverDPdy = dFdy(P);
}
#endif
