// Declared properties (src/base/properties.h): defaults, validation with JSON paths, and the
// OIT registry's schemas read from the scene's "render.oit" object or its string form.
#include "base/error.h"
#include "base/properties.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <string>

using nlohmann::json;

namespace veil {
namespace {

PropertySchema schema() {
    PropertySchema s;
    s.boolean("on", true, "a switch")
        .integer("count", 8, 1, 64, "a count", "[Enderton11 sec. 3.1]")
        .real("bias", 5e-6, 0.0, 0.999, "a bias", "[Munstermann18 sec. 5.3]")
        .color("tint", {1, 0.5f, 0}, "a colour")
        .choice("mode", "a", {"a", "b"}, "a choice");
    return s;
}

std::string resolveError(const json& values) {
    return test::errorOf(
        [&] { schema().resolve(values, "scene.json: /render/oit", "OIT technique 'x'"); });
}

TEST(PropertiesTest, DefaultsFillEveryKey) {
    const Properties p = schema().defaults();
    EXPECT_TRUE(p.getBool("on"));
    EXPECT_EQ(p.getInt("count"), 8);
    EXPECT_DOUBLE_EQ(p.getDouble("bias"), 5e-6);
    EXPECT_EQ(p.getVec3("tint"), glm::vec3(1, 0.5f, 0));
    EXPECT_EQ(p.getString("mode"), "a");
    EXPECT_EQ(p.values().size(), 5u);
}

TEST(PropertiesTest, GivenValuesReplaceDefaultsAndTypeIsIgnored) {
    const Properties p = schema().resolve(
        {{"type", "x"}, {"count", 16}, {"bias", 1e-4}, {"mode", "b"}, {"on", false}}, "w");
    EXPECT_EQ(p.getInt("count"), 16);
    EXPECT_DOUBLE_EQ(p.getDouble("bias"), 1e-4);
    EXPECT_EQ(p.getString("mode"), "b");
    EXPECT_FALSE(p.getBool("on"));
    EXPECT_FALSE(p.values().contains("type"));
    EXPECT_EQ(schema().resolve({{"count", 4.0}}, "w").getInt("count"), 4); // integral float
}

TEST(PropertiesTest, UnknownKeysNameThePathAndListTheAccepted) {
    const std::string e = resolveError({{"cuont", 3}});
    EXPECT_NE(e.find("scene.json: /render/oit/cuont"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown key of OIT technique 'x'"), std::string::npos) << e;
    EXPECT_NE(e.find("accepted: on, count, bias, tint, mode"), std::string::npos) << e;
}

TEST(PropertiesTest, BadValuesAreErrorsNamingTheKey) {
    EXPECT_NE(resolveError({{"count", 0}}).find("/render/oit/count: value 0 out of range [1, 64]"),
              std::string::npos)
        << resolveError({{"count", 0}});
    EXPECT_NE(resolveError({{"count", 2.5}}).find("expected an integer"), std::string::npos);
    EXPECT_NE(resolveError({{"bias", 1.0}}).find("out of range [0, 0.999]"), std::string::npos);
    EXPECT_NE(resolveError({{"bias", "small"}}).find("expected a number"), std::string::npos);
    EXPECT_NE(resolveError({{"bias", 1e39}}).find("does not fit a finite 32-bit float"),
              std::string::npos)
        << resolveError({{"bias", 1e39}});
    EXPECT_NE(resolveError({{"on", 1}}).find("expected true or false"), std::string::npos);
    EXPECT_NE(resolveError({{"mode", "c"}}).find("is not one of a, b"), std::string::npos);
    EXPECT_NE(resolveError({{"tint", {1, 2}}}).find("expected an array of 3 numbers"),
              std::string::npos);
    EXPECT_NE(resolveError({{"tint", {1, -2, 0}}}).find("/render/oit/tint/1"), std::string::npos);
    EXPECT_NE(resolveError(json::array()).find("expected an object of properties"),
              std::string::npos);
    // A deep value is described, never dumped.
    json deep = 0;
    for (int i = 0; i < 2000; ++i)
        deep = json::array({deep});
    EXPECT_LT(resolveError({{"bias", deep}}).size(), 200u);
}

TEST(PropertiesTest, DeclarationsAreChecked) {
    PropertySchema s;
    s.integer("n", 1, 1, 4, "n");
    EXPECT_THROW(s.integer("n", 1, 1, 4, "again"), Error);       // declared twice
    EXPECT_THROW(s.integer("m", 9, 1, 4, "bad default"), Error); // default outside its range
    EXPECT_THROW(s.withDefault("n", 5), Error);
    EXPECT_THROW(s.withDefault("nope", 1), Error);
    Properties p = s.defaults();
    EXPECT_THROW(p.getFloat("missing"), Error);
    EXPECT_THROW(p.getBool("n"), Error); // wrong type
    EXPECT_THROW(p.set("n", 7), Error);
    EXPECT_EQ(p.set("n", 3).getInt("n"), 3);
}

TEST(PropertiesTest, EveryOitTechniqueDeclaresValidDefaults) {
    const auto& registry = oit::Registry::instance();
    ASSERT_GE(registry.all().size(), 17u);
    for (const auto& t : registry.all()) {
        const Properties p = registry.resolve(t.name, json(), "t");
        EXPECT_EQ(p.values().size(), t.properties.all().size()) << t.name;
        for (const PropertyDecl& d : t.properties.all()) {
            EXPECT_FALSE(d.doc.empty()) << t.name << "." << d.key;
            EXPECT_EQ(d.key.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_"),
                      std::string::npos)
                << t.name << "." << d.key;
        }
    }
    // Variants of one technique differ in their defaults only.
    EXPECT_FALSE(registry.resolve("phenomenological-nodiff", json(), "t").getBool("diffusion"));
    EXPECT_TRUE(registry.resolve("phenomenological", json(), "t").getBool("diffusion"));
    EXPECT_TRUE(
        registry.resolve("phenomenological-volume", json(), "t").getBool("volume_refraction"));
    // docs/oit.md#moment-constants biases per set.
    EXPECT_DOUBLE_EQ(registry.resolve("moment-p6", json(), "t").getDouble("bias"), 5e-6);
    EXPECT_DOUBLE_EQ(registry.resolve("moment-t3-16", json(), "t").getDouble("bias"), 6.5e-4);
    EXPECT_FALSE(registry.find("moment-p4")->properties.find("wrapping_zone"));
    EXPECT_TRUE(registry.find("moment-t4")->properties.find("wrapping_zone"));
    // b_0 in RGBA16F by default for p6-half only (bench/RESULTS.md, oit-cost), half only.
    EXPECT_TRUE(registry.resolve("moment-p6-half", json(), "t").getBool("b0_half"));
    EXPECT_FALSE(registry.resolve("moment-t4-half", json(), "t").getBool("b0_half"));
    EXPECT_FALSE(registry.find("moment-p6")->properties.find("b0_half"));
    EXPECT_EQ(registry.resolve("stochastic", json(), "t").getInt("samples"), 8);
}

json sceneDoc(const json& oit) {
    return {{"render", {{"oit", oit}}},
            {"cameras", json::array({{{"name", "c"}, {"position", {0, 0, 5}}}})}};
}

TEST(PropertiesTest, SceneTakesTheObjectAndTheStringForm) {
    scene::Scene s = scene::parseScene(sceneDoc({{"type", "moment-p6"}, {"bias", 1e-5}}), ".");
    EXPECT_EQ(s.render.oit, "moment-p6");
    EXPECT_EQ(s.render.oitProperties, json({{"bias", 1e-5}}));
    EXPECT_NE(s.render.oitWhere.find("/render/oit"), std::string::npos);
    s = scene::parseScene(sceneDoc("wboit"), ".");
    EXPECT_EQ(s.render.oit, "wboit");
    EXPECT_TRUE(s.render.oitProperties.is_null());
    // No type: the default technique with these properties (what --set render.oit.KEY=V
    // makes of a scene without "oit"); the technique's schema checks them when it is created.
    s = scene::parseScene(sceneDoc({{"samples", 4}}), ".");
    EXPECT_EQ(s.render.oit, "blend");
    EXPECT_EQ(s.render.oitProperties, json({{"samples", 4}}));
    EXPECT_THROW(scene::parseScene(sceneDoc({{"type", 4}}), "."), Error);
}

TEST(PropertiesTest, OverridesOpenTheStringFormIntoAnObject) {
    json doc = sceneDoc("stochastic");
    scene::applyOverrides(doc, {"render.oit.samples=16"});
    EXPECT_EQ(doc["render"]["oit"], json({{"type", "stochastic"}, {"samples", 16}}));
    scene::applyOverrides(doc, {"render.oit.type=moment-p6", "render.oit=blend"});
    EXPECT_EQ(doc["render"]["oit"], "blend");
    const scene::Scene s = scene::parseScene(
        [] {
            json d = sceneDoc("blend");
            scene::applyOverrides(d, {"render.oit.type=stochastic", "render.oit.passes=2"});
            return d;
        }(),
        ".");
    EXPECT_EQ(s.render.oit, "stochastic");
    EXPECT_EQ(oit::Registry::instance()
                  .resolve(s.render.oit, s.render.oitProperties, s.render.oitWhere)
                  .getInt("passes"),
              2);
}

} // namespace
} // namespace veil
