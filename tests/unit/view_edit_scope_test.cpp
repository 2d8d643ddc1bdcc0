// What an edit in the viewer redoes (session::classifyOverride, overrideEditEffect), derived
// from the edit effects declared with the scene's values (scene/scene_values.cpp). The keys
// of each class are written out here, independently of the declarations: every declared key
// is checked, so a value declared live, or no longer live, fails until this list says so too.
#include "scene/scene_values.h"
#include "viewer/session/view_session.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

using namespace veil;
using scene::EditEffect;
using session::classifyOverride;
using session::overrideEditEffect;
using session::OverrideScope;

namespace {

template <class S>
std::set<std::string> declaredKeys(const std::vector<scene::ValueDecl<S>>& decls) {
    std::set<std::string> keys;
    for (const auto& d : decls)
        keys.insert(d.key);
    return keys;
}

// Each key of `keys` under `prefix`: Live with `effect` when in `live`, else Renderer.
void expectClasses(const std::string& prefix, const std::set<std::string>& keys,
                   const std::set<std::string>& live, EditEffect effect) {
    for (const std::string& k : keys) {
        const std::string key = prefix + k;
        const bool isLive = live.count(k) > 0;
        EXPECT_EQ(classifyOverride(key), isLive ? OverrideScope::Live : OverrideScope::Renderer)
            << key;
        EXPECT_EQ(overrideEditEffect(key), isLive ? effect : EditEffect::Rebuild) << key;
    }
}

} // namespace

TEST(ViewEditScopeTest, RenderValues) {
    std::set<std::string> keys = declaredKeys(scene::renderValueDecls());
    ASSERT_TRUE(keys.count("width") && keys.count("height"));
    EXPECT_EQ(classifyOverride("render.width"), OverrideScope::Size);
    EXPECT_EQ(classifyOverride("render.height"), OverrideScope::Size);
    keys.erase("width");
    keys.erase("height");
    // Per-pixel values, and the progressive bake's time per frame: copied, nothing redrawn.
    const std::set<std::string> perPixel = {"exposure",
                                            "ambient",
                                            "background",
                                            "tonemap",
                                            "fog_scattered_light_budget_ms",
                                            "fog_scattered_light_frame_ms"};
    // Read by a technique marching the media: the shadow maps are redrawn.
    const std::set<std::string> shadowMaps = {"fog_steps", "fog_jitter"};
    std::set<std::string> rest;
    for (const std::string& k : keys)
        if (!perPixel.count(k) && !shadowMaps.count(k)) rest.insert(k);
    expectClasses("render.", perPixel, perPixel, EditEffect::Live);
    expectClasses("render.", shadowMaps, shadowMaps, EditEffect::ShadowMaps);
    expectClasses("render.", rest, {}, EditEffect::Rebuild);
    for (const std::string& k : perPixel)
        EXPECT_TRUE(keys.count(k)) << k;
    for (const std::string& k : shadowMaps)
        EXPECT_TRUE(keys.count(k)) << k;
    // Only the value itself, not a component of it.
    EXPECT_EQ(classifyOverride("render.background.0"), OverrideScope::Renderer);
    EXPECT_EQ(classifyOverride("render.oit"), OverrideScope::Oit);
    EXPECT_EQ(classifyOverride("render.oit.samples"), OverrideScope::Oit);
    EXPECT_EQ(classifyOverride("render.shadows"), OverrideScope::Renderer);
    EXPECT_EQ(classifyOverride("render.shadows.type"), OverrideScope::Renderer);
    EXPECT_EQ(classifyOverride("render"), OverrideScope::Renderer);
}

TEST(ViewEditScopeTest, LightValues) {
    // Every light key but the ones that change which lights have maps (and the name); the
    // aim (direction, target) is not a declared value but is live too.
    const std::set<std::string> live = {"color",  "intensity",  "position",  "direction",
                                        "target", "inner_cone", "outer_cone"};
    const std::set<std::string> rebuild = {"shadows", "type", "name"};
    std::set<std::string> keys = declaredKeys(scene::lightValueDecls());
    for (const std::string& k : keys)
        EXPECT_TRUE(live.count(k) || rebuild.count(k)) << k << " is in neither list";
    keys.insert(live.begin(), live.end());
    keys.insert(rebuild.begin(), rebuild.end());
    expectClasses("lights.0.", keys, live, EditEffect::Relight);
    expectClasses("lights.12.", keys, live, EditEffect::Relight);
    // A component of a light's value is live as the value.
    EXPECT_EQ(classifyOverride("lights.0.color.1"), OverrideScope::Live);
    EXPECT_EQ(overrideEditEffect("lights.0.position.2"), EditEffect::Relight);
    EXPECT_EQ(classifyOverride("lights.0"), OverrideScope::Renderer);
    EXPECT_EQ(classifyOverride("lights"), OverrideScope::Renderer);
}

TEST(ViewEditScopeTest, MaterialValues) {
    // The shading values; alpha and transmission can change the shadow technique's classes.
    const std::set<std::string> live = {"base_color", "roughness", "metalness", "emission"};
    const std::set<std::string> keys = declaredKeys(scene::materialValueDecls());
    for (const std::string& k : live)
        EXPECT_TRUE(keys.count(k)) << k;
    expectClasses("materials.0.", keys, live, EditEffect::ShadowMaps);
    expectClasses("materials.glass.", keys, live, EditEffect::ShadowMaps);
    EXPECT_EQ(classifyOverride("materials.0.base_color.2"), OverrideScope::Live);
    EXPECT_EQ(classifyOverride("materials.0.alpha.0"), OverrideScope::Renderer);
}

TEST(ViewEditScopeTest, VolumeValues) {
    // A grid volume's optics (the session rebuilds for homogeneous fog).
    const std::set<std::string> live = {"density_scale", "albedo", "anisotropy", "emission"};
    const std::set<std::string> keys = declaredKeys(scene::volumeValueDecls());
    for (const std::string& k : live)
        EXPECT_TRUE(keys.count(k)) << k;
    expectClasses("volumes.0.", keys, live, EditEffect::Relight);
    // Only the value itself, not a component of it.
    EXPECT_EQ(classifyOverride("volumes.0.albedo.1"), OverrideScope::Renderer);
    EXPECT_EQ(classifyOverride("volumes.0.path"), OverrideScope::Renderer);
}

TEST(ViewEditScopeTest, CamerasAndTheRest) {
    for (const std::string& k : declaredKeys(scene::cameraValueDecls()))
        EXPECT_EQ(classifyOverride("cameras.0." + k), OverrideScope::Camera) << k;
    EXPECT_EQ(classifyOverride("cameras"), OverrideScope::Camera);
    for (const char* key : {"objects.0.material", "time.frame", "meshes.0.path", "exposure", ""})
        EXPECT_EQ(classifyOverride(key), OverrideScope::Renderer) << key;
}
