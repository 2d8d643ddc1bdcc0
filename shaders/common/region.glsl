// A compute pass over part of its target (pass::Context::region, dispatchRegion()):
// the dispatch covers the region's size, its origin is added here.
uniform ivec4 region; // x0 y0 x1 y1, x1 and y1 exclusive

// This invocation's pixel (texel) of a target of `size`; false outside the region or target.
bool regionPixel(ivec2 size, out ivec2 p) {
    p = ivec2(gl_GlobalInvocationID.xy) + region.xy;
    return all(lessThan(p, min(size, region.zw)));
}
