// Frames held on the GPU by a volume (fog/gpu_volume.h GpuVolume::replace with
// GridConversion::gpuKey): the held frames' texture bytes, counted from the sizes GL reports,
// stay within the budget, the least recently shown frame is dropped first, a held frame shown
// again uploads nothing and its textures hold the texels a fresh upload of it makes, and with
// a budget of 0 every frame uploads.
#include "gl_fixture.h"

#include "fog/gpu_volume.h"
#include "grid/grid_conversion.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace veil::test {

namespace {

class GpuVolumeFramesTest : public GlTest {};

int max3D() {
    GLint m = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &m);
    return m;
}

// A 12^3 box of voxels (a dense texture) whose values depend on `seed`, held under `key`.
volume::GridConversion frame(int seed, const std::string& key, std::size_t holdBytes) {
    openvdb::FloatGrid grid(0.0f);
    auto acc = grid.getAccessor();
    for (int z = 0; z < 12; ++z)
        for (int y = 0; y < 12; ++y)
            for (int x = 0; x < 12; ++x)
                acc.setValue({x, y, z}, float((x * 7 + y * 3 + z + seed * 13) % 17) / 16.0f);
    volume::GridConversion c = volume::convertGrid(grid, {}, max3D());
    c.gpuKey = key;
    c.gpuHoldBytes = holdBytes;
    return c;
}

// Bytes of `t` from the sizes and format GL reports (R16F data: 2 a texel).
std::size_t textureBytes(const gpu::Texture& t) {
    GLint w = 0, h = 0, d = 0, format = 0;
    glGetTextureLevelParameteriv(t.id(), 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(t.id(), 0, GL_TEXTURE_HEIGHT, &h);
    glGetTextureLevelParameteriv(t.id(), 0, GL_TEXTURE_DEPTH, &d);
    glGetTextureLevelParameteriv(t.id(), 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
    EXPECT_EQ(format, GL_R16F);
    return std::size_t(w) * std::size_t(h) * std::size_t(d) * 2;
}

std::vector<std::uint16_t> texels(const gpu::Texture& t) {
    std::vector<std::uint16_t> out(textureBytes(t) / 2);
    glGetTextureImage(t.id(), 0, GL_RED, GL_HALF_FLOAT, GLsizei(out.size() * 2), out.data());
    return out;
}

} // namespace

TEST_F(GpuVolumeFramesTest, HeldBytesStayWithinTheBudgetLeastRecentlyShownDroppedFirst) {
    std::size_t frameBytes = 0;
    {
        const volume::GpuVolume probe(frame(0, "", 0), glm::mat4(1.0f));
        ASSERT_TRUE(probe.stats().dense);
        frameBytes = textureBytes(probe.data());
    }
    ASSERT_GT(frameBytes, 0u);
    const std::size_t budget = frameBytes * 5 / 2; // two frames
    std::vector<volume::GridConversion> frames;
    for (int i = 0; i < 5; ++i)
        frames.push_back(frame(i, "frame " + std::to_string(i), budget));
    volume::GpuVolume v(frames[0], glm::mat4(1.0f));
    EXPECT_EQ(v.stats().uploads, 1u);
    for (int i = 1; i < 5; ++i) {
        v.replace(frames[std::size_t(i)], glm::mat4(1.0f));
        EXPECT_EQ(v.stats().uploads, std::size_t(i + 1));
        EXPECT_EQ(v.stats().heldFrames, 2u) << "frame " << i;
        EXPECT_EQ(v.stats().heldBytes, 2 * frameBytes) << "frame " << i;
        EXPECT_LE(v.stats().heldBytes, budget);
    }
    // Held: 3 and 4. Showing 3 again makes 4 the least recently shown: 0 drops 4, not 3.
    v.replace(frames[3], glm::mat4(1.0f));
    EXPECT_EQ(v.stats().uploads, 5u);
    EXPECT_EQ(v.stats().reshown, 1u);
    v.replace(frames[0], glm::mat4(1.0f));
    EXPECT_EQ(v.stats().uploads, 6u);
    v.replace(frames[3], glm::mat4(1.0f));
    EXPECT_EQ(v.stats().uploads, 6u) << "frame 3 was dropped";
    v.replace(frames[4], glm::mat4(1.0f));
    EXPECT_EQ(v.stats().uploads, 7u) << "frame 4 was kept";
    EXPECT_LE(v.stats().heldBytes, budget);
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(GpuVolumeFramesTest, HeldFrameShownAgainUploadsNothingAndHoldsItsTexels) {
    const std::size_t budget = std::size_t(64) << 20;
    const volume::GridConversion a = frame(1, "a", budget), b = frame(2, "b", budget);
    volume::GpuVolume v(a, glm::mat4(1.0f));
    v.replace(b, glm::mat4(1.0f));
    v.replace(a, glm::mat4(1.0f));
    EXPECT_EQ(v.stats().uploads, 2u);
    EXPECT_EQ(v.stats().reshown, 1u);
    const volume::GpuVolume freshA(frame(1, "", 0), glm::mat4(1.0f));
    const volume::GpuVolume freshB(frame(2, "", 0), glm::mat4(1.0f));
    ASSERT_NE(texels(freshA.data()), texels(freshB.data()));
    EXPECT_EQ(texels(v.data()), texels(freshA.data()));
    // The object transform is the one given now, not the one of the first showing.
    const glm::mat4 moved = glm::translate(glm::mat4(1.0f), glm::vec3(3.0f, 0.0f, 0.0f));
    v.replace(b, moved);
    EXPECT_EQ(v.stats().uploads, 2u);
    EXPECT_EQ(texels(v.data()), texels(freshB.data()));
    EXPECT_EQ(v.indexToWorld(), moved * b.indexToWorld);
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(GpuVolumeFramesTest, BudgetZeroUploadsEveryFrame) {
    const volume::GridConversion a = frame(1, "a", 0), b = frame(2, "b", 0);
    volume::GpuVolume v(a, glm::mat4(1.0f));
    for (int i = 0; i < 4; ++i)
        v.replace(i % 2 ? a : b, glm::mat4(1.0f));
    EXPECT_EQ(v.stats().uploads, 5u);
    EXPECT_EQ(v.stats().reshown, 0u);
    EXPECT_EQ(v.stats().heldFrames, 1u);
    VEIL_EXPECT_NO_GL_ERROR();
}

} // namespace veil::test
