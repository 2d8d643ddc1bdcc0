// The frame's screen-space ambient obscurance (src/frame/stages/ambient_occlusion.h) and
// phenomenological's inferred AO at partial coverage [McGuire17 sec. 6, Listing 2]:
//  - the GPU estimator against a CPU double-precision evaluation of the same estimator (SAO's
//    sum over the spiral, on a z pyramid the test builds itself from the depth buffer), and
//    the bilateral blur against the same blur in double on the GPU's raw AO;
//  - a flat open floor gives AO = 1 (every sample lies in the tangent plane: v.n = 0);
//  - Listing 2 written again in double on the GPU's own AO and depth buffers, at the partial
//    coverage edge of a card in front of a floor-wall corner;
//  - AO off: the frame renders bit for bit what it did before AO existed (a golden made by the
//    main branch's binary from tests/gl/data/ao_off_scene.json).
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "io/image_io.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <vector>

namespace veil::test {

namespace {

const double kTwoPi = 6.28318530717958647692;

// A GL texture level, bottom row first (gl_FragCoord order).
struct Level {
    int w = 0, h = 0;
    std::vector<double> v;
    double at(int x, int y) const { return v[std::size_t(y) * w + x]; }
};

Level readLevel(const gpu::Texture& t, int level, GLenum format) {
    Level l;
    glGetTextureLevelParameteriv(t.id(), level, GL_TEXTURE_WIDTH, &l.w);
    glGetTextureLevelParameteriv(t.id(), level, GL_TEXTURE_HEIGHT, &l.h);
    std::vector<float> f(std::size_t(l.w) * l.h);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(t.id(), level, format, GL_FLOAT, GLsizei(f.size() * sizeof(float)), f.data());
    l.v.assign(f.begin(), f.end());
    return l;
}

// The camera's projection in double (column-major as GLSL: P[col][row]).
struct Projection {
    double P[4][4];
    double W, H;
    double viewDistance(double d) const { // window depth -> positive view distance
        const double ndc = 2.0 * d - 1.0;
        return -(P[3][2] - ndc * P[3][3]) / (ndc * P[2][3] - P[2][2]);
    }
    glm::dvec3 viewPosition(double px, double py, double z) const {
        const double nx = 2.0 * px / W - 1.0, ny = 2.0 * py / H - 1.0;
        const double w = -P[2][3] * z + P[3][3];
        return {(nx * w + P[2][0] * z - P[3][0]) / P[0][0],
                (ny * w + P[2][1] * z - P[3][1]) / P[1][1], -z};
    }
    double pixelsPerUnit(double z) const { return 0.5 * H * P[1][1] / (-P[2][3] * z + P[3][3]); }
};

Projection projectionOf(const frame::Renderer& r) {
    Projection p;
    const glm::mat4 m = r.camera().projection(float(r.width()) / float(r.height()));
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k)
            p.P[c][k] = m[c][k];
    p.W = r.width();
    p.H = r.height();
    return p;
}

std::uint32_t aoHash(std::uint32_t x, std::uint32_t y) { // shaders/frame/ao/ao_common.glsl
    std::uint32_t h = (x * 0x8da6b343u) ^ (y * 0xd8163841u);
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    h ^= h >> 12;
    return h;
}

struct SaoParams {
    double radius, intensity, contrast, bias, epsilon;
    int samples, turns, levels;
};

// The estimator of shaders/frame/ao/sao.comp, written again from SAO's description in double:
// z pyramid from the depth buffer (rotated-grid subsampling), normals from the closer
// neighbour per axis, s samples on a spiral of tau turns, A = max(0, 1 - 2 sigma / s sum)^k.
Level cpuSao(const Level& depth, const Projection& p, const SaoParams& q, double far) {
    std::vector<Level> pyr(1);
    pyr[0] = depth;
    for (double& d : pyr[0].v)
        d = p.viewDistance(d);
    for (int m = 0; m + 1 < q.levels; ++m) {
        const Level& a = pyr[m];
        Level b;
        b.w = std::max(1, depth.w >> (m + 1));
        b.h = std::max(1, depth.h >> (m + 1));
        b.v.resize(std::size_t(b.w) * b.h);
        for (int y = 0; y < b.h; ++y)
            for (int x = 0; x < b.w; ++x) {
                const int sx = std::min(2 * x + ((y & 1) ^ 1), a.w - 1);
                const int sy = std::min(2 * y + ((x & 1) ^ 1), a.h - 1);
                b.v[std::size_t(y) * b.w + x] = a.at(sx, sy);
            }
        pyr.push_back(b);
    }
    auto pos = [&](int x, int y, int m) {
        const Level& l = pyr[m];
        int tx = std::clamp(x >> m, 0, l.w - 1), ty = std::clamp(y >> m, 0, l.h - 1);
        const double z = l.at(tx, ty);
        for (int k = m; k > 0; --k) { // back to the level-0 pixel the z came from
            const int nx = std::min(2 * tx + ((ty & 1) ^ 1), pyr[k - 1].w - 1);
            const int ny = std::min(2 * ty + ((tx & 1) ^ 1), pyr[k - 1].h - 1);
            tx = nx;
            ty = ny;
        }
        return p.viewPosition(tx + 0.5, ty + 0.5, z);
    };
    Level out = depth;
    const int W = depth.w, H = depth.h;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const double zC = pyr[0].at(x, y);
            double& o = out.v[std::size_t(y) * W + x];
            if (zC >= far * 0.999) {
                o = 1.0;
                continue;
            }
            const glm::dvec3 P = p.viewPosition(x + 0.5, y + 0.5, zC);
            const glm::dvec3 px = pos(std::min(x + 1, W - 1), y, 0) - P;
            const glm::dvec3 nx = P - pos(std::max(x - 1, 0), y, 0);
            const glm::dvec3 py = pos(x, std::min(y + 1, H - 1), 0) - P;
            const glm::dvec3 ny = P - pos(x, std::max(y - 1, 0), 0);
            const glm::dvec3 dx = std::abs(px.z) < std::abs(nx.z) ? px : nx;
            const glm::dvec3 dy = std::abs(py.z) < std::abs(ny.z) ? py : ny;
            glm::dvec3 n = glm::normalize(glm::cross(dx, dy));
            if (glm::dot(n, P) > 0.0) n = -n;
            const double hr = q.radius * p.pixelsPerUnit(zC);
            const double phi = kTwoPi * double(aoHash(x, y) & 0xffffu) / 65536.0;
            double sum = 0.0;
            for (int i = 0; i < q.samples; ++i) {
                const double a = (i + 0.5) / q.samples;
                const double theta = kTwoPi * a * q.turns + phi;
                const double h = a * hr;
                const int qx = std::clamp(x + int(std::round(h * std::cos(theta))), 0, W - 1);
                const int qy = std::clamp(y + int(std::round(h * std::sin(theta))), 0, H - 1);
                int msb = -1;
                for (int v = int(h); v > 0; v >>= 1)
                    ++msb;
                const int m = std::clamp(msb - 3, 0, q.levels - 1);
                const glm::dvec3 v = pos(qx, qy, m) - P;
                const double vv = glm::dot(v, v);
                if (vv < q.radius * q.radius)
                    sum += std::max(0.0, glm::dot(v, n) - q.bias * zC) / (vv + q.epsilon);
            }
            const double A = std::max(0.0, 1.0 - 2.0 * q.intensity / q.samples * sum);
            o = std::pow(A, q.contrast);
        }
    return out;
}

// shaders/frame/ao/blur.comp in double, both axes, on `raw`.
Level cpuBlur(const Level& raw, const Level& z, int R, int stride, double sharpness, double far) {
    Level cur = raw;
    for (int axis = 0; axis < 2; ++axis) {
        Level next = cur;
        for (int y = 0; y < raw.h; ++y)
            for (int x = 0; x < raw.w; ++x) {
                const double zC = z.at(x, y);
                if (zC >= far * 0.999) continue;
                const double sigma = 0.5 * R;
                double s = 0.0, ws = 0.0;
                for (int t = -R; t <= R; ++t) {
                    const int qx = std::clamp(x + (axis == 0 ? t * stride : 0), 0, raw.w - 1);
                    const int qy = std::clamp(y + (axis == 1 ? t * stride : 0), 0, raw.h - 1);
                    const double w =
                        std::exp(-double(t * t) / (2 * sigma * sigma)) *
                        std::max(0.0, 1.0 - sharpness * std::abs(z.at(qx, qy) - zC) / zC);
                    s += w * cur.at(qx, qy);
                    ws += w;
                }
                next.v[std::size_t(y) * raw.w + x] = s / ws;
            }
        cur = next;
    }
    return cur;
}

// Camera looking along -z at height 0.5; floor y = 0, wall face at z = -0.5, optional card.
nlohmann::json cornerScene(bool wall, bool card, nlohmann::json ao) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 160, "height": 90, "camera": "main", "ambient": [1, 1, 1],
                 "background": [0, 0, 0], "tonemap": "clamp",
                 "oit": {"type": "phenomenological", "refraction": false, "diffusion": false,
                         "self_modulation": false}},
      "cameras": [{"name": "main", "type": "perspective", "position": [0, 0.5, 3],
                   "target": [0, 0.5, 0], "fov_y": 45, "near": 0.1, "far": 20}],
      "lights": [],
      "materials": {"black": {"base_color": 0.0, "roughness": 0.9},
                    "card": {"base_color": 0.8, "roughness": 0.9, "coverage_edge": 0.2}},
      "objects": [{"shape": {"type": "plane", "size": [8, 8]}, "material": "black"}]})");
    if (wall)
        doc["objects"].push_back({{"shape", {{"type", "box"}, {"size", {8, 3, 0.2}}}},
                                  {"material", "black"},
                                  {"transform", {{"translate", {0, 1.5, -0.6}}}}});
    if (card) // 1.6 x 0.6, facing the camera, 0.25 in front of the wall, touching the floor
        doc["objects"].push_back(
            {{"shape", {{"type", "plane"}, {"size", {1.6, 0.6}}}},
             {"material", "card"},
             {"transform", {{"translate", {0.2, 0.3, -0.25}}, {"rotate", {90, 0, 0}}}}});
    doc["render"]["ao"] = std::move(ao);
    return doc;
}

SaoParams paramsOf(const Properties& p, int levels) {
    return {p.getDouble("radius"),    p.getDouble("intensity"),
            p.getDouble("contrast"),  p.getDouble("bias"),
            p.getDouble("epsilon"),   p.getInt("samples"),
            p.getInt("spiral_turns"), levels};
}

} // namespace

class AmbientOcclusionGLTest : public GlTest {};

// Tolerance: the GPU stores AO as R16F (half an ulp: 2^-12 relative below 1) and evaluates in
// float; z from float depth differs from double by ~1e-7 relative. A sample whose rounded
// pixel or radius test flips between float and double (ties at a depth edge) changes one
// term of 11: allowed on at most 1% of the pixels; the mean difference must stay at 5e-4.
TEST_F(AmbientOcclusionGLTest, EstimatorMatchesCpuDoubleOnTheDepthBuffer) {
    const nlohmann::json ao = {{"enabled", true}, {"radius", 0.6},    {"blur_radius", 4},
                               {"samples", 11},   {"intensity", 1.0}, {"contrast", 1.5}};
    const scene::Scene sc = scene::parseScene(cornerScene(true, false, ao), sourceDir());
    frame::Renderer renderer(sc, info());
    renderer.render();
    VEIL_EXPECT_NO_GL_ERROR();
    const frame::AmbientOcclusion* a = renderer.ambientOcclusion();
    ASSERT_NE(a, nullptr);
    const Level depth = readLevel(*renderer.resourceTexture("depth"), 0, GL_DEPTH_COMPONENT);
    const Level raw = readLevel(*renderer.resourceTexture("ao.raw"), 0, GL_RED);
    const Level blurred = readLevel(*renderer.resourceTexture("ao.visibility"), 0, GL_RED);
    const Level z0 = readLevel(*renderer.resourceTexture("ao.depth"), 0, GL_RED);
    const Projection p = projectionOf(renderer);
    const double far = renderer.camera().farPlane;
    const Level cpu = cpuSao(depth, p, paramsOf(a->properties(), a->levels()), far);

    int bad = 0, dark = 0;
    double sumDiff = 0.0, minAo = 1.0;
    for (std::size_t i = 0; i < cpu.v.size(); ++i) {
        const double d = std::abs(raw.v[i] - cpu.v[i]);
        sumDiff += d;
        if (d > 2e-3) ++bad;
        minAo = std::min(minAo, cpu.v[i]);
        if (cpu.v[i] < 0.8) ++dark;
    }
    const int n = int(cpu.v.size());
    EXPECT_LE(bad, n / 100) << "pixels off the CPU estimator by more than 2e-3";
    EXPECT_LE(sumDiff / n, 5e-4);
    // Not a trivial image: the corner is dark, the open floor far from it is not.
    EXPECT_LT(minAo, 0.3);
    EXPECT_GT(dark, n / 20);
    EXPECT_GT(cpu.at(5, 5), 0.99); // near floor, bottom left, a metre in front of the wall

    // The blur, in double on the GPU's own raw AO (so estimator ties do not propagate):
    // R16F storage of both passes, 2e-3.
    const Properties& pr = a->properties();
    const Level cb = cpuBlur(raw, z0, pr.getInt("blur_radius"), pr.getInt("blur_stride"),
                             pr.getDouble("blur_sharpness"), far);
    double worst = 0.0;
    for (std::size_t i = 0; i < cb.v.size(); ++i)
        worst = std::max(worst, std::abs(blurred.v[i] - cb.v[i]));
    EXPECT_LE(worst, 2e-3);
}

TEST_F(AmbientOcclusionGLTest, FlatOpenFloorIsUnoccluded) {
    // Every sample lies in the floor's plane: v.n = 0 up to float error, under the bias; so
    // A = 1, with or without the pyramid (a far sample is placed at the pixel its z came from).
    for (int levels : {1, 5}) {
        const scene::Scene sc = scene::parseScene(
            cornerScene(false, false, {{"enabled", true}, {"radius", 0.6}, {"mip_levels", levels}}),
            sourceDir());
        frame::Renderer renderer(sc, info());
        renderer.render();
        const Level ao = readLevel(renderer.ambientOcclusion()->visibility(), 0, GL_RED);
        const double tol = 1e-3; // R16F holds 1 exactly; float error in v.n is under the bias
        double lo = 1.0;
        for (double v : ao.v)
            lo = std::min(lo, v);
        EXPECT_GE(lo, 1.0 - tol) << "mip_levels " << levels;
    }
}

// [McGuire17 Listing 2] on the CPU in double at the card's left and right edge bands (0 < alpha <
// 1, gradient along x toward the opaque interior), on the GPU's AO buffer and depth. With black
// opaque surfaces, no lights and ambient 1 the edge pixel is alpha * 0.8 * AO_inferred over
// black, so AO_inferred = hdr(inferred_ao on) / hdr(off). Tolerance: two R16F-accumulated
// values (2^-11 relative each) and the resolve in float: 3e-3.
TEST_F(AmbientOcclusionGLTest, InferredAoAtPartialCoverageMatchesListing2) {
    const nlohmann::json ao = {{"enabled", true}, {"radius", 0.6}, {"blur_radius", 2}};
    nlohmann::json doc = cornerScene(true, true, ao);
    const scene::Scene on = scene::parseScene(doc, sourceDir());
    doc["render"]["oit"]["inferred_ao"] = false;
    const scene::Scene off = scene::parseScene(doc, sourceDir());
    frame::Renderer rOn(on, info()), rOff(off, info());
    rOn.render();
    const Level hdrOn = readLevel(rOn.hdrTexture(), 0, GL_GREEN);
    const Level aoBuf = readLevel(rOn.ambientOcclusion()->visibility(), 0, GL_RED);
    const Level depth = readLevel(*rOn.resourceTexture("depth"), 0, GL_DEPTH_COMPONENT);
    rOff.render();
    const Level hdrOff = readLevel(rOff.hdrTexture(), 0, GL_GREEN);
    VEIL_EXPECT_NO_GL_ERROR();
    const Projection p = projectionOf(rOn);

    // The card: plane z = -0.25 (view distance 3.25), x in [-0.6, 1.0], y in [0, 0.6].
    const double zCard = 3.25, edge = 0.2;
    auto sampleAO = [&](double fx, double fy, double z1, double& s, double& w) {
        const int cx = std::clamp(int(fx), 0, aoBuf.w - 1); // ivec2() truncates, then clamp
        const int cy = std::clamp(int(fy), 0, aoBuf.h - 1);
        const double z2 = p.viewDistance(depth.at(cx, cy));
        const double weight = 0.01 / (0.01 + std::abs(z1 - z2));
        s += aoBuf.at(cx, cy) * weight;
        w += weight;
    };
    int tested = 0, occluded = 0;
    double worst = 0.0;
    for (int y = 0; y < p.H; ++y)
        for (int x = 0; x < p.W; ++x) {
            const glm::dvec3 v = p.viewPosition(x + 0.5, y + 0.5, zCard);
            const double u = (v.x + 0.6) / 1.6, t = (v.y + 0.5) / 0.6; // view y 0 = world 0.5
            if (u <= 0.0 || u >= 1.0 || t <= 0.0 || t >= 1.0) continue;
            const double du = std::min(u, 1.0 - u), dv = std::min(t, 1.0 - t);
            // The left/right bands only, away from the corners and from the band's ends.
            if (du >= edge * 0.9 || du < edge * 0.1 || dv < edge + 0.1) continue;
            const double alpha = du / edge;
            const double off = hdrOff.at(x, y);
            ASSERT_NEAR(off, 0.8 * alpha, 4e-3) << "card geometry at pixel " << x << "," << y;
            // Listing 2, line branch: dir = gradient / |gradient| = (+-1, 0).
            const double dir = u < 0.5 ? 1.0 : -1.0;
            double s = 0.0, w = 0.0;
            for (int k = 0; k < 12; ++k)
                sampleAO(x + 0.5 + dir * k * 3.0, y + 0.5, zCard, s, w);
            const double inferred = std::clamp(s / std::max(0.01, w), 0.0, 1.0);
            const double gpu = hdrOn.at(x, y) / off;
            worst = std::max(worst, std::abs(gpu - inferred));
            EXPECT_NEAR(gpu, inferred, 3e-3) << "pixel " << x << "," << y << " alpha " << alpha;
            ++tested;
            if (inferred < 0.9) ++occluded;
        }
    EXPECT_GE(tested, 20);
    EXPECT_GE(occluded, 3) << "the chosen pixels should include occluded ones (near the floor)";
    RecordProperty("worst", std::to_string(worst));
}

// AO off (no render.ao, or enabled false): the image main rendered before AO existed, bit for
// bit (same llvmpipe; tests/gl/data/ao_off_golden.exr, made by main's veil from the scene;
// remade on 2026-12-01 when phenomenological's refraction target became RG16F: the old image
// differs from it in 55 of 15552 values by at most 2.4e-4, one RGBA16F step; remade on
// 2026-12-04 for the receiver-plane shadow bias: the floor's acne pattern is gone, and with the
// slope forced to zero the new code renders the old image bit for bit).
TEST_F(AmbientOcclusionGLTest, AoOffGivesTheOldImageBitExact) {
    const auto dir = sourceDir() / "tests/gl/data";
    nlohmann::json doc;
    std::ifstream(dir / "ao_off_scene.json") >> doc;
    const ImageF golden = io::readImage(dir / "ao_off_golden.exr");
    for (bool explicitOff : {false, true}) {
        if (explicitOff) doc["render"]["ao"] = {{"enabled", false}, {"radius", 2.0}};
        const scene::Scene sc = scene::parseScene(doc, dir);
        frame::Renderer renderer(sc, info());
        renderer.render();
        EXPECT_EQ(renderer.ambientOcclusion(), nullptr);
        const ImageF img = renderer.readHdr();
        ASSERT_EQ(img.width, golden.width);
        ASSERT_EQ(img.height, golden.height);
        int diff = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x)
                for (int c = 0; c < 3; ++c)
                    if (img.at(x, y, c) != golden.at(x, y, c)) ++diff;
        EXPECT_EQ(diff, 0) << "values differing from the pre-AO golden (explicit off: "
                           << explicitOff << ")";
    }
}

} // namespace veil::test
