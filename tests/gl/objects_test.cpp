// Move-only RAII GL objects (Magnum's model) and texture readback.
#include "gl_fixture.h"

#include "base/error.h"
#include "gpu/objects.h"
#include "gpu/readback.h"
#include "gpu/timer.h"

#include <type_traits>

namespace veil::test {

static_assert(!std::is_copy_constructible_v<gpu::Buffer>);
static_assert(!std::is_copy_assignable_v<gpu::Texture>);
static_assert(std::is_nothrow_move_constructible_v<gpu::Framebuffer>);
static_assert(std::is_nothrow_move_assignable_v<gpu::VertexArray>);

class ObjectsTest : public GlTest {};

TEST_F(ObjectsTest, MoveTransfersOwnership) {
    gpu::Buffer a;
    const GLuint id = a.id();
    ASSERT_NE(id, 0u);
    {
        gpu::Buffer b(std::move(a));
        EXPECT_EQ(a.id(), 0u);
        EXPECT_EQ(b.id(), id);
        EXPECT_TRUE(glIsBuffer(id));
    }
    EXPECT_FALSE(glIsBuffer(id)) << "the moved-to owner must delete the name";
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(ObjectsTest, MoveAssignDeletesPreviousName) {
    gpu::Texture a(GL_TEXTURE_2D);
    gpu::Texture b(GL_TEXTURE_2D);
    const GLuint ida = a.id(), idb = b.id();
    b = std::move(a);
    EXPECT_EQ(b.id(), ida);
    a = gpu::Texture(gpu::NoCreate); // drops b's old name, which a now holds
    EXPECT_FALSE(glIsTexture(idb));
    EXPECT_TRUE(glIsTexture(ida));
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(ObjectsTest, ReleaseAndWrap) {
    gpu::Buffer a;
    const GLuint id = a.release();
    EXPECT_EQ(a.id(), 0u);
    EXPECT_TRUE(glIsBuffer(id));
    { gpu::Buffer b = gpu::Buffer::wrap(id); }
    EXPECT_FALSE(glIsBuffer(id));
}

TEST_F(ObjectsTest, NoCreateOwnsNothing) {
    gpu::Framebuffer f(gpu::NoCreate);
    EXPECT_FALSE(static_cast<bool>(f));
}

TEST_F(ObjectsTest, TextureReadbackIsTopRowFirst) {
    // Upload 2x2 with GL's bottom row = (1,2); readback returns the top row first.
    gpu::Texture t(GL_TEXTURE_2D);
    t.storage2D(1, GL_R32F, 2, 2);
    const float data[4] = {1, 2, 3, 4}; // GL row 0 (bottom) = 1,2; row 1 (top) = 3,4
    glTextureSubImage2D(t.id(), 0, 0, 0, 2, 2, GL_RED, GL_FLOAT, data);
    ImageF img = gpu::readTexture(t, 1);
    ASSERT_EQ(img.width, 2);
    EXPECT_EQ(img.at(0, 0, 0), 3.0f);
    EXPECT_EQ(img.at(1, 0, 0), 4.0f);
    EXPECT_EQ(img.at(0, 1, 0), 1.0f);
    EXPECT_EQ(img.at(1, 1, 0), 2.0f);
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(ObjectsTest, BufferRejectsWritesPastItsEnd) {
    gpu::Buffer b;
    b.setStorage(16, nullptr);
    const char bytes[32] = {};
    EXPECT_THROW(b.setSubData(8, 16, bytes), Error);
    EXPECT_NO_THROW(b.setSubData(0, 16, bytes));
}

TEST_F(ObjectsTest, TimerReportsScopesInOrder) {
    gpu::GpuTimer timer(info().softwareRenderer ? gpu::GpuTimer::Mode::CpuFinish
                                                : gpu::GpuTimer::Mode::Query);
    timer.begin("a");
    glFlush();
    timer.end();
    timer.begin("b");
    timer.end();
    EXPECT_THROW(timer.end(), Error);
    auto times = timer.collect();
    ASSERT_EQ(times.size(), 2u);
    EXPECT_EQ(times[0].name, "a");
    EXPECT_EQ(times[1].name, "b");
    EXPECT_GE(times[0].milliseconds, 0.0);
    EXPECT_TRUE(timer.collect().empty());
}

} // namespace veil::test
