// Renderer::setOitTechnique: the replaced technique's programs are released (its own,
// transparent and fog-emission programs, `reference`'s fog segments), so switching back and
// forth keeps as many programs as a renderer built with the technique; the pass list names
// the new technique's targets; a failing switch keeps the old technique and adds nothing.
#include "frame/renderer.h"
#include "gl_fixture.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace veil::test {

namespace {

scene::Scene fogGlassScene() {
    return scene::parseScene(nlohmann::json::parse(R"({
      "render": {"width": 32, "height": 24, "oit": "blend", "fog_steps": 8},
      "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0.5, 0]}],
      "lights": [{"type": "directional", "direction": [0, -1, -0.3], "intensity": 2}],
      "materials": {"glass": {"base_color": 1, "alpha": 0.5}},
      "objects": [{"shape": {"type": "box", "size": [1, 1, 0.1]}, "material": "glass"}],
      "volumes": [{"procedural": "sphere", "size": 1, "voxel_size": 0.1, "density_scale": 2}]
    })"),
                             ".");
}

bool writes(const frame::Renderer& r, const std::string& pass, const std::string& resource) {
    const frame::Pass* p = r.passes().find(pass);
    return p && std::find(p->writes.begin(), p->writes.end(), resource) != p->writes.end();
}

} // namespace

class OitSwitchGLTest : public GlTest {};

TEST_F(OitSwitchGLTest, SwitchReleasesTheOldTechniquesPrograms) {
    const scene::Scene sc = fogGlassScene();
    // What a renderer built with each technique holds.
    std::map<std::string, std::size_t> fresh;
    for (const std::string oit : {"blend", "wboit", "reference", "moment-p6"}) {
        frame::Renderer r(sc, info(), {0, 0, "", oit});
        fresh[oit] = r.liveProgramCount();
    }
    frame::Renderer r(sc, info());
    ASSERT_EQ(r.liveProgramCount(), fresh["blend"]);
    for (int round = 0; round < 2; ++round)
        for (const std::string oit : {"wboit", "reference", "moment-p6", "blend"}) {
            SCOPED_TRACE(oit + " round " + std::to_string(round));
            r.setOitTechnique(oit, nlohmann::json::object());
            EXPECT_EQ(r.liveProgramCount(), fresh[oit]);
            r.render(); // the released programs are not used
            VEIL_EXPECT_NO_GL_ERROR();
        }
    // The pass list follows the technique: its targets are frame resources.
    r.setOitTechnique("wboit", nlohmann::json::object());
    EXPECT_TRUE(writes(r, "transparent", "oit.wboit.accum"));
    EXPECT_TRUE(writes(r, "transparent", "oit.wboit.revealage"));
    ASSERT_NE(r.resourceTexture("oit.wboit.accum"), nullptr);
    r.setOitTechnique("reference", nlohmann::json::object());
    EXPECT_FALSE(writes(r, "transparent", "oit.wboit.accum"));
    EXPECT_TRUE(writes(r, "resolve", "oit.reference.fragments_per_pixel"));
    // A failing switch (a bad property) keeps the technique and its programs.
    const std::size_t before = r.liveProgramCount();
    EXPECT_THROW(r.setOitTechnique("wboit", {{"no_such_key", 1}}), Error);
    EXPECT_THROW(r.setOitTechnique("moment-p6", {{"bias", -1}}), Error);
    EXPECT_EQ(r.oitName(), "reference");
    EXPECT_EQ(r.liveProgramCount(), before);
    r.render();
    VEIL_EXPECT_NO_GL_ERROR();
}

} // namespace veil::test
