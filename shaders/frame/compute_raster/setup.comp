#version 450 core
// Triangle setup [Laine11 sec. 4.1], one invocation per triangle of one object (the frame
// dispatches once per object, its uniforms and mesh buffers bound: frame::dispatchObjects):
// the vertex transform of the hardware path (frame/raster_setup.glsl), clipping of the
// polygon against the near plane (as GL clips) and a guard band around the viewport (so that
// window coordinates fit the fixed-point edge functions: +-16384 pixels), snapping to 8
// sub-pixel bits, orientation to positive area (no culling of back faces: the transparent
// pass draws both sides), and the pixel bounds; zero-area triangles cover nothing.
#include "veil:raster_setup"
#include "raster.glsl"

layout(local_size_x = 64) in;

uniform uint triangleBase;   // this object's first input triangle
uniform uint objectIndex;
uniform uint triangleCount;  // input triangles of the frame (the first records)
uniform uint extraCapacity;  // records after them for further subtriangles
uniform ivec2 viewportSize;
uniform float guardBand;     // clip |x|, |y| <= guardBand * w

struct ClipVertex {
    vec4 position;
    float a[SURFACE_ATTRIBUTES];
};

ClipVertex mixVertex(ClipVertex p, ClipVertex q, float t) {
    ClipVertex r;
    r.position = mix(p.position, q.position, t);
    for (int k = 0; k < SURFACE_ATTRIBUTES; ++k) r.a[k] = mix(p.a[k], q.a[k], t);
    return r;
}

// Signed distance to clip plane `plane` (0: near, 1..4: guard band -x, +x, -y, +y); >= 0 inside.
float planeDistance(vec4 c, int plane) {
    if (plane == 0) return c.z + c.w;
    float g = guardBand * c.w;
    if (plane == 1) return g + c.x;
    if (plane == 2) return g - c.x;
    if (plane == 3) return g + c.y;
    return g - c.y;
}

#define MAX_POLY 9
ClipVertex poly[MAX_POLY];
ClipVertex clipped[MAX_POLY];
int polyCount;

void clipAgainst(int plane) {
    int n = 0;
    for (int i = 0; i < polyCount; ++i) {
        ClipVertex p = poly[i], q = poly[(i + 1) % polyCount];
        float dp = planeDistance(p.position, plane), dq = planeDistance(q.position, plane);
        if (dp >= 0.0) clipped[n++] = p;
        if ((dp >= 0.0) != (dq >= 0.0)) clipped[n++] = mixVertex(p, q, dp / (dp - dq));
    }
    polyCount = n;
    for (int i = 0; i < n; ++i) poly[i] = clipped[i];
}

// Window position of a clip-space vertex: fixed-point x, y and depth.
ivec2 snapped(vec4 c, out float depth) {
    vec3 ndc = c.xyz / c.w;
    depth = ndc.z * 0.5 + 0.5;
    vec2 window = (ndc.xy * 0.5 + 0.5) * vec2(viewportSize);
    return ivec2(round(window * float(RASTER_SUBPIXEL)));
}

void writeTriangle(uint record, ClipVertex v0, ClipVertex v1, ClipVertex v2, uint subtriangles,
                   uint extraFirst) {
    float z0, z1, z2;
    ivec2 p0 = snapped(v0.position, z0), p1 = snapped(v1.position, z1),
          p2 = snapped(v2.position, z2);
    // Twice the signed area, exact in double (coordinates below 2^23).
    double area = double(p1.x - p0.x) * double(p2.y - p0.y) -
                  double(p1.y - p0.y) * double(p2.x - p0.x);
    RasterTriangle t;
    if (area < 0.0lf) { // clockwise: swap two vertices (the rasterizer wants positive area)
        ClipVertex tv = v1; v1 = v2; v2 = tv;
        ivec2 tp = p1; p1 = p2; p2 = tp;
        float tz = z1; z1 = z2; z2 = tz;
    }
    t.x = ivec4(p0.x, p1.x, p2.x, int(objectIndex));
    t.y = ivec4(p0.y, p1.y, p2.y, int((extraFirst << 3) | subtriangles));
    t.z = vec4(z0, z1, z2, 0.0);
    t.invW = vec4(1.0 / v0.position.w, 1.0 / v1.position.w, 1.0 / v2.position.w, 0.0);
    // Pixel x is covered only if its centre x * S + S / 2 lies in [min, max].
    const int S = RASTER_SUBPIXEL, H = RASTER_SUBPIXEL / 2;
    ivec2 lo = min(min(p0, p1), p2) - H, hi = max(max(p0, p1), p2) - H;
    ivec2 first = max((lo + (S - 1)) >> 8, ivec2(0));      // ceil(lo / S) (S = 2^8)
    ivec2 last = min(hi >> 8, viewportSize - 1);             // floor(hi / S)
    t.bounds = area == 0.0lf ? ivec4(1, 1, 0, 0) : ivec4(first, last);
    uint base = record * uint(3 * SURFACE_ATTRIBUTES);
    for (uint k = 0u; k < uint(SURFACE_ATTRIBUTES); ++k) {
        rasterAttributes[base + k] = v0.a[k];
        rasterAttributes[base + SURFACE_ATTRIBUTES + k] = v1.a[k];
        rasterAttributes[base + 2 * SURFACE_ATTRIBUTES + k] = v2.a[k];
    }
    rasterTriangles[record] = t;
}

void main() {
    uint local = gl_GlobalInvocationID.x;
    if (local == 0u) {
        vec4 r[SURFACE_RECORD_VEC4S];
        surfaceRecord(r);
        for (int i = 0; i < SURFACE_RECORD_VEC4S; ++i)
            rasterObjects[objectIndex * SURFACE_RECORD_VEC4S + uint(i)] = r[i];
    }
    if (local >= surfaceTriangleCount()) return;
    uint record = triangleBase + local;
    for (uint c = 0u; c < 3u; ++c) {
        ClipVertex v;
        v.position = surfaceVertex(surfaceTriangleIndex(local, c), v.a);
        poly[c] = v;
    }
    polyCount = 3;
    // Outcodes: clip only against the planes some vertex lies behind; reject when all do.
    for (int plane = 0; plane < 5; ++plane) {
        int outside = 0;
        for (int i = 0; i < polyCount; ++i)
            outside += planeDistance(poly[i].position, plane) < 0.0 ? 1 : 0;
        if (outside == polyCount) { polyCount = 0; break; }
        if (outside > 0) clipAgainst(plane);
        if (polyCount < 3) { polyCount = 0; break; }
    }
    if (polyCount == 0) {
        rasterTriangles[record].y.w = 0; // covers nothing
        rasterTriangles[record].bounds = ivec4(1, 1, 0, 0);
        return;
    }
    // A fan of polyCount - 2 triangles: the first in this record, the others in the extra
    // region (counted past its capacity: the host grows it and runs setup again).
    uint subtriangles = uint(polyCount - 2), extraFirst = 0u;
    if (subtriangles > 1u) {
        extraFirst = atomicAdd(rasterExtraRecords, subtriangles - 1u);
        if (extraFirst + subtriangles - 1u > extraCapacity) subtriangles = 1u;
    }
    writeTriangle(record, poly[0], poly[1], poly[2], subtriangles, triangleCount + extraFirst);
    for (uint k = 1u; k < subtriangles; ++k)
        writeTriangle(triangleCount + extraFirst + k - 1u, poly[0], poly[k + 1u], poly[k + 2u],
                      subtriangles, 0u);
}
