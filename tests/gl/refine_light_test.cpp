// The tiled refinement's light transmittance volumes (frame::Renderer::refineStep, volume::
// FogPass::updateLightVolumesSlab, docs/viewer.md "Slow drivers"): computed in z slabs, one
// per refineStep() call (one UI frame in the viewer), they equal the volumes computed in one
// piece by render() bit for bit, and so does the refined frame.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "texel_bits.h"
#include "fog/fog_pass.h"

#include <cstdint>
#include <vector>

namespace veil::test {

namespace {

// The R32F texels as stored (bits, not values: the comparison is exact).
std::vector<std::uint32_t> floatTexels(const gpu::Texture& t) {
    return texelBits<std::uint32_t>(t, GL_RED, GL_FLOAT, 1);
}

} // namespace

class RefineLightTest : public GlTest {};

// datasets/scenes/fog.json (one smoke volume lit by a spot light) at 96 x 64 in 48 px tiles
// (2 x 2) with opaque shadows, so that the fog shadows itself through its light transmittance
// volume. Every refineStep() computes at most one slab (kRefineLightSlabTexels z slices) and
// a step that computes a slab runs no tile; the slabs are ceil(depth / slab) per volume, and
// after them the tiles; the volume and the ldr frame equal render()'s bit for bit (each texel
// depends on its own coordinate only, in both the same shader on the same values).
TEST_F(RefineLightTest, SlabsEqualTheVolumeInOnePieceOneSlabPerStep) {
    const scene::Scene s =
        scene::loadScene(sourceDir() / "datasets/scenes/fog.json",
                         {"render.width=96", "render.height=64", "render.shadows.type=opaque",
                          "render.shadows.size=128", "render.fog_resolution=2"});
    frame::Renderer whole(s, info());
    ASSERT_NE(whole.fog(), nullptr);
    const gpu::Texture* wholeLight = whole.fog()->lightTransmittanceTexture(0);
    ASSERT_NE(wholeLight, nullptr);
    whole.render();
    const std::vector<std::uint32_t> expected = floatTexels(*wholeLight);
    const std::vector<std::uint8_t> expectedLdr = rgba8(whole.ldrTexture());

    frame::Renderer tiled(s, info());
    const volume::FogPass& fog = *tiled.fog();
    const int slabs0 = fog.lightSlabs();
    tiled.beginRefinement(48);
    EXPECT_EQ(fog.lightSlabs(), slabs0) << "the first call computes no slab";
    const int depth = fog.lightTransmittanceTexture(0)->depth();
    const int slab = frame::Renderer::kRefineLightSlabTexels;
    const int wantSlabs = (depth + slab - 1) / slab;
    ASSERT_GT(wantSlabs, 1) << "the volume would be computed in one piece";
    int steps = 0, slabSteps = 0, tileSteps = 0;
    bool done = false;
    while (!done && steps < 1000) {
        const int before = fog.lightSlabs(), tilesBefore = tiled.refinement().done;
        done = tiled.refineStep();
        ++steps;
        const int slabsNow = fog.lightSlabs() - before,
                  tilesNow = tiled.refinement().done - tilesBefore;
        EXPECT_LE(slabsNow, 1) << "step " << steps;
        EXPECT_LE(slabsNow + tilesNow, 1) << "step " << steps << ": a slab and a tile";
        if (slabsNow == 1) {
            EXPECT_EQ(tileSteps, 0) << "a slab after a tile (the tiles read the volume)";
            ++slabSteps;
        }
        tileSteps += tilesNow;
    }
    VEIL_EXPECT_NO_GL_ERROR();
    ASSERT_TRUE(done);
    EXPECT_EQ(slabSteps, wantSlabs);
    EXPECT_EQ(tiled.refinement().lightSlabs, wantSlabs);
    EXPECT_EQ(tileSteps, 4);
    const std::vector<std::uint32_t> got = floatTexels(*fog.lightTransmittanceTexture(0));
    ASSERT_EQ(got.size(), expected.size());
    std::size_t differ = 0, lit = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        differ += got[i] != expected[i];
        lit += expected[i] != 0x3c00 && expected[i] != 0; // neither 1 nor 0: shadowed smoke
    }
    EXPECT_EQ(differ, 0u) << "of " << got.size() << " texels";
    EXPECT_GT(lit, got.size() / 100) << "the volume should hold partial transmittance";
    const std::vector<std::uint8_t> ldr = rgba8(tiled.ldrTexture());
    ASSERT_EQ(ldr.size(), expectedLdr.size());
    std::size_t ldrDiffer = 0;
    for (std::size_t i = 0; i < ldr.size(); ++i)
        ldrDiffer += ldr[i] != expectedLdr[i];
    EXPECT_EQ(ldrDiffer, 0u) << "bytes of the refined frame";
}

} // namespace veil::test
