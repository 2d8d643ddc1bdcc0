// GL state isolation between passes and techniques (docs/architecture.md "Declared GL state": a
// pass sets all the state it needs and relies on none another left behind). Every technique
// available here renders one scene (opaque surfaces, glass, particles, fog) in a fresh context;
// then all of them render again in one context in three orders, with a slice-map voxelization in
// between. Each image must equal the fresh one bit for bit and no GL error may be pending.
#include "gl/gl_fixture.h"

#include "frame/renderer.h"
#include "gpu/context.h"
#include "gpu/gl.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "voxelize/gpu_voxelizer.h"
#include "voxelize/triangles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <random>

namespace veil::test {

namespace {

constexpr int kWidth = 64, kHeight = 36;

scene::Scene testScene() {
    std::ifstream in(sourceDir() / "datasets/scenes/oit-smoke-glass.json");
    nlohmann::json doc = nlohmann::json::parse(in, nullptr, true, true);
    // A small smoke ball too, so the fog marcher and its emission pass are in every frame.
    doc["volumes"] = nlohmann::json::parse(R"([{"name": "fog", "procedural": "smoke-ball",
        "size": 1.2, "voxel_size": 0.1, "density_scale": 2.0,
        "transform": {"translate": [0.6, 1.0, 0.3]}}])");
    doc["render"]["fog_steps"] = 24;
    return scene::parseScene(doc, sourceDir() / "datasets/scenes");
}

ImageF renderOnce(const scene::Scene& sc, const gpu::ContextInfo& info, const std::string& oit) {
    frame::Renderer renderer(sc, info, {kWidth, kHeight, "", oit});
    renderer.render();
    ImageF img = renderer.readHdr();
    const GLenum error = glGetError();
    EXPECT_EQ(error, static_cast<GLenum>(GL_NO_ERROR))
        << oit << ": GL error 0x" << std::hex << error;
    return img;
}

// A voxelization between frames, as `veil view` or a suite might run one (8 RGBA32UI targets
// with a logic op: the draw a leaked dual-source blend function breaks).
void voxelizeSomething(const gpu::ContextInfo& info) {
    const voxelize::Triangles tris = voxelize::fromMesh(scene::makeSphere(1.0f, 16, 8));
    voxelize::SliceMap grid =
        voxelize::makeOrthoGrid({-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, 32, 32, 1024);
    voxelize::GpuVoxelizer voxelizer(info);
    voxelizer.upload(tris);
    voxelizer.voxelize(grid, {voxelize::Method::Raster, false, false});
    EXPECT_GT(grid.countSet(), 0u);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)) << "voxelizer";
}

} // namespace

class StateOrderGLTest : public GlTest {};

TEST_F(StateOrderGLTest, TechniquesInAnyOrderGiveTheFreshContextImages) {
    const scene::Scene sc = testScene();
    std::vector<std::string> names;
    for (const auto& t : oit::Registry::instance().all())
        if (!t.isAvailable || t.isAvailable(info())) names.push_back(t.name);
    ASSERT_GE(names.size(), 10u);

    std::map<std::string, ImageF> fresh;
    for (const std::string& name : names) {
        gpu::HeadlessContext own; // current until destroyed
        fresh[name] = renderOnce(sc, own.info(), name);
    }
    context_->makeCurrent();

    std::vector<std::vector<std::string>> orders{names, names, names};
    std::reverse(orders[1].begin(), orders[1].end());
    std::shuffle(orders[2].begin(), orders[2].end(), std::mt19937(7));
    for (std::size_t o = 0; o < orders.size(); ++o) {
        for (const std::string& name : orders[o]) {
            const ImageF img = renderOnce(sc, info(), name);
            const ImageDiff d = compareImages(img, fresh[name], 4);
            EXPECT_EQ(d.maxAbs, 0.0) << name << " in order " << o << " differs from its "
                                     << "fresh-context image (RMSE " << d.rmse << "); see "
                                     << writeFailureImages("state_order_" + name, img, fresh[name]);
            if (o == 1) {
                SCOPED_TRACE("voxelization after " + name);
                voxelizeSomething(info());
            }
        }
    }
}

} // namespace veil::test
