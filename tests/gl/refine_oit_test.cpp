// The tiled refinement (frame::Renderer::refineStep, docs/viewer.md "Slow drivers") with every
// registered OIT technique: each technique's resolve and compute passes dispatch over the
// tile and its margin only (pass::Context::region), and the refined frame equals the
// frame in one piece bit for bit; a tile's passes leave hdr outside its region untouched.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "io/image_io.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "texel_bits.h"

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace veil::test {

namespace {

// The RGBA16F texels as stored (bits, not values: the comparisons are exact).
std::vector<std::uint16_t> halfTexels(const gpu::Texture& t) {
    return texelBits<std::uint16_t>(t, GL_RGBA, GL_HALF_FLOAT, 4);
}

// datasets/scenes/fog.json (glass, a smoke volume and haze everywhere, so that every pixel
// has a transparent contribution) at 96 x 64: 32 px tiles make 3 x 2 tiles, and with the
// fog marched at 1/2 resolution its joint-bilateral upsampling reads across tile edges (what
// the margin is for).
scene::Scene fogScene() {
    return scene::loadScene(sourceDir() / "datasets/scenes/fog.json",
                            {"render.width=96", "render.height=64", "render.fog_steps=32",
                             "render.fog_resolution=2", "render.shadows.type=opaque",
                             "render.shadows.size=128"});
}

constexpr int kTile = 32;

// Every registered technique the context offers (the others are skipped, as the registry
// would refuse them).
std::vector<std::string> techniqueNames() {
    std::vector<std::string> names;
    for (const auto& t : oit::Registry::instance().all())
        names.push_back(t.name);
    return names;
}

frame::RendererOptions withTechnique(const std::string& name) {
    frame::RendererOptions o;
    o.oit = name;
    // `reference`'s default pool grows instead of dropping fragments (docs/viewer.md
    // "Limits": a dropping pool could keep more in a tile than in the whole frame).
    return o;
}

bool available(const std::string& name, const gpu::ContextInfo& info) {
    const oit::TechniqueInfo& t = oit::Registry::instance().get(name);
    return !t.isAvailable || t.isAvailable(info);
}

void refineAll(frame::Renderer& r) {
    r.beginRefinement(kTile);
    int steps = 0;
    while (!r.refineStep() && ++steps < 1000) {
    }
    ASSERT_FALSE(r.refinement().active) << "the refinement did not complete";
}

} // namespace

class RefineOitTest : public GlTest, public ::testing::WithParamInterface<std::string> {};

// Refined in 6 tiles, the hdr frame (RGBA16F bits) and the ldr frame equal render()'s
// exactly: each pixel of the tile runs the same shaders on the same values in both (a pixel's
// result reads its own pixel and, for the fog's upsampling, the fog texels the march covers
// for the tile; phenomenological's gather reads up to its refineMarginPx() away, exact for
// refraction offsets up to 16 px, see docs/viewer.md "Slow drivers"). So any difference is a pass
// that reads or writes outside its region.
//
// And a tile away from the frame's origin (tile 4: x 32..63, y 32..63; its region that and
// the technique's margin, Renderer::refineMarginPx()), refined after render() has left the whole
// frame's accumulation in the technique's targets: a sentinel put in hdr before the tile survives
// outside the region bit for bit (no resolve, compute pass or copy wrote there; phenomenological's
// 32 px margin makes the region the whole frame: nothing outside), and inside the region no
// pixel keeps it (the tile starts from the opaque image, and the haze is everywhere).
TEST_P(RefineOitTest, RefinedFrameEqualsTheFrameInOnePieceAndTilesKeepToTheirRegion) {
    const std::string name = GetParam();
    if (!available(name, info())) GTEST_SKIP() << name << " is not available on this context";
    const scene::Scene s = fogScene();
    const int w = s.render.width, h = s.render.height;
    frame::Renderer whole(s, info(), withTechnique(name));
    whole.render();
    const std::vector<std::uint16_t> wantHdr = halfTexels(whole.hdrTexture());
    const std::vector<std::uint8_t> wantLdr = rgba8(whole.ldrTexture());

    frame::Renderer tiled(s, info(), withTechnique(name)); // fresh targets
    refineAll(tiled);
    EXPECT_EQ(tiled.refinement().tiles, 6);
    VEIL_EXPECT_NO_GL_ERROR();
    const std::vector<std::uint16_t> hdr = halfTexels(tiled.hdrTexture());
    const std::vector<std::uint8_t> ldr = rgba8(tiled.ldrTexture());
    ASSERT_EQ(hdr.size(), wantHdr.size());
    std::size_t differ = 0, firstDiffer = hdr.size();
    for (std::size_t i = 0; i < hdr.size(); ++i) {
        if (hdr[i] == wantHdr[i]) continue;
        if (differ++ == 0) firstDiffer = i;
    }
    EXPECT_EQ(differ, 0u) << name << ": hdr channels differ of " << hdr.size()
                          << "; the first at pixel (" << (firstDiffer / 4) % w << ", "
                          << (firstDiffer / 4) / w << ")";
    EXPECT_TRUE(ldr == wantLdr) << name << ": the ldr frame differs";
    io::writeImage(outputDir() / ("refine-oit-" + name + ".png"), tiled.readLdr());
    double sum = 0.0;
    for (std::size_t i = 0; i < ldr.size(); ++i)
        if (i % 4 != 3) sum += ldr[i];
    EXPECT_GT(sum / (double(ldr.size()) * 0.75), 8.0) << name << ": a black frame";

    // The sentinel, in `whole` (its targets hold the whole frame's accumulation).
    whole.beginRefinement(kTile);
    int steps = 0;
    while (whole.refinement().done < 4 && ++steps < 1000)
        whole.refineStep();
    ASSERT_EQ(whole.refinement().done, 4);
    const float sentinel[4] = {0.25f, 0.5f, 3.0f, 0.75f};
    glClearTexImage(whole.hdrTexture().id(), 0, GL_RGBA, GL_FLOAT, sentinel);
    const std::vector<std::uint16_t> before = halfTexels(whole.hdrTexture());
    ASSERT_FALSE(whole.refineStep()); // not the last tile (that copies the frame back)
    ASSERT_EQ(whole.refinement().lastStep, frame::Renderer::Refinement::Step::Tile);
    const glm::ivec4 region = whole.refinement().lastRegion;
    const int m = whole.refineMarginPx();
    ASSERT_EQ(region, glm::ivec4(std::max(32 - m, 0), std::max(32 - m, 0), std::min(64 + m, w),
                                 std::min(64 + m, h)));
    VEIL_EXPECT_NO_GL_ERROR();
    const std::vector<std::uint16_t> after = halfTexels(whole.hdrTexture());
    std::size_t outsideChanged = 0, insideKept = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = (std::size_t(y) * w + x) * 4;
            bool same = true;
            for (int c = 0; c < 3; ++c) // not alpha: some resolves write 1, some keep it
                same = same && after[i + c] == before[i + c];
            const bool inside = x >= region.x && x < region.z && y >= region.y && y < region.w;
            if (inside)
                insideKept += same;
            else
                outsideChanged += !same;
        }
    }
    EXPECT_EQ(outsideChanged, 0u) << name << ": pixels outside the tile's region written";
    EXPECT_EQ(insideKept, 0u) << name << ": pixels inside the region kept the sentinel";
}

class RefinePhenomenologicalLowResTest : public GlTest,
                                         public ::testing::WithParamInterface<int> {};

// phenomenological's particles at 1/2 and 1/4 resolution (datasets/scenes/oit-smoke-glass.json:
// particle clouds around a glass ball, at 96 x 64): the low-resolution depth key, the
// particles' draws and clears and the upsampling keep to the low-resolution texels the
// region's upsampling reads (the region divided by the factor, rounded outward, plus 2
// texels), and the refined frame equals the frame in one piece bit for bit.
TEST_P(RefinePhenomenologicalLowResTest, RefinedFrameEqualsTheFrameInOnePiece) {
    const int factor = GetParam();
    const scene::Scene s =
        scene::loadScene(sourceDir() / "datasets/scenes/oit-smoke-glass.json",
                         {"render.width=96", "render.height=64", "render.shadows.size=128"});
    frame::RendererOptions o;
    o.oit = "phenomenological";
    o.oitProperties = {{"particle_downsample", factor}};
    frame::Renderer whole(s, info(), o);
    whole.render();
    frame::Renderer tiled(s, info(), o);
    refineAll(tiled);
    VEIL_EXPECT_NO_GL_ERROR();
    const std::vector<std::uint16_t> want = halfTexels(whole.hdrTexture()),
                                     got = halfTexels(tiled.hdrTexture());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < got.size(); ++i)
        differ += got[i] != want[i];
    EXPECT_EQ(differ, 0u) << "hdr channels differ at 1/" << factor;
    const std::vector<std::uint8_t> ldr = rgba8(tiled.ldrTexture());
    EXPECT_TRUE(ldr == rgba8(whole.ldrTexture()));
    io::writeImage(outputDir() / ("refine-phen-lowres-" + std::to_string(factor) + ".png"),
                   tiled.readLdr());
    // The low-resolution pass contributed: the frame differs from the one with the particles
    // at full resolution (so the comparison above covered particle pixels).
    frame::RendererOptions full = o;
    full.oitProperties = {{"particle_downsample", 1}};
    frame::Renderer fullRes(s, info(), full);
    fullRes.render();
    EXPECT_FALSE(ldr == rgba8(fullRes.ldrTexture())) << "no particles at 1/" << factor;
}

INSTANTIATE_TEST_SUITE_P(Factors, RefinePhenomenologicalLowResTest, ::testing::Values(2, 4));

INSTANTIATE_TEST_SUITE_P(Registered, RefineOitTest, ::testing::ValuesIn(techniqueNames()),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                             std::string n = p.param;
                             for (char& c : n)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return n;
                         });

} // namespace veil::test
