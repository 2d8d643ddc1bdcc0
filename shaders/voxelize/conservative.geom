#version 450
// Conservative rasterization without GL_NV_conservative_raster: each triangle becomes its
// NDC bounding rectangle dilated by half a pixel (every pixel whose square touches the
// triangle's bounds has its centre inside), and the fragment stage keeps the pixels whose
// square overlaps the triangle (2D separating axes) and sets every slice between the
// triangle's min and max depth over the pixel square. With NV_CONSERVATIVE defined (the
// driver dilates itself) the triangle is emitted as is.
// THREE_AXIS: emit only triangles whose dominant normal axis is uAxis (three-axis method;
// the fragment stage then tests the pixel's inscribed diamond, [Schwarz10]'s
// 6-separating criterion).
layout(triangles) in;
layout(triangle_strip, max_vertices = 4) out;

in vec3 vWorld[];
uniform vec2 uViewport; // pixels
uniform int uAxis;
flat out vec3 gA;
flat out vec3 gB;
flat out vec3 gC;

void main() {
#ifdef THREE_AXIS
    vec3 nrm = abs(cross(vWorld[1] - vWorld[0], vWorld[2] - vWorld[0]));
    int dominant = nrm.x >= nrm.y && nrm.x >= nrm.z ? 0 : (nrm.y >= nrm.z ? 1 : 2);
    if (dominant != uAxis) return;
#endif
    vec3 p[3];
    for (int i = 0; i < 3; ++i) {
        // The grid fits the scene, so vertices lie in front of a perspective grid camera.
        if (gl_in[i].gl_Position.w <= 0.0) return;
        p[i] = gl_in[i].gl_Position.xyz / gl_in[i].gl_Position.w;
    }
    gA = p[0];
    gB = p[1];
    gC = p[2];
#ifdef NV_CONSERVATIVE
    // Hardware conservative rasterization drops triangles whose projection is (nearly)
    // degenerate (edge-on to the view: measured on the H100, the single-view method then
    // missed 89% of the voxels of a 1M-triangle scene). Those get the bounding quad below;
    // the fragment shader's separating-axis tests keep both paths exact.
    vec2 e1 = (p[1].xy - p[0].xy) * uViewport * 0.5, e2 = (p[2].xy - p[0].xy) * uViewport * 0.5;
    if (abs(e1.x * e2.y - e1.y * e2.x) > 0.5) { // twice the area in pixels^2
        for (int i = 0; i < 3; ++i) {
            gl_Position = vec4(p[i], 1.0);
            EmitVertex();
        }
        EndPrimitive();
        return;
    }
#endif
    {
        vec2 half_ = 1.0 / uViewport + 1e-6; // half a pixel in NDC, plus rounding slack
        vec2 lo = min(p[0].xy, min(p[1].xy, p[2].xy)) - half_;
        vec2 hi = max(p[0].xy, max(p[1].xy, p[2].xy)) + half_;
        gl_Position = vec4(lo.x, lo.y, 0.0, 1.0);
        EmitVertex();
        gl_Position = vec4(hi.x, lo.y, 0.0, 1.0);
        EmitVertex();
        gl_Position = vec4(lo.x, hi.y, 0.0, 1.0);
        EmitVertex();
        gl_Position = vec4(hi.x, hi.y, 0.0, 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
