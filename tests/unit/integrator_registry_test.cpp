// The CPU integrators by name (src/integrators/registry.h): both found, both rendering an
// absorbing box through the registry to its Beer-Lambert transmittance (and so to each other),
// the path tracer's properties read from the scene's render.pathtraced, an unknown name refused
// with the known ones.
#include "integrators/registry.h"

#include "base/error.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>

namespace veil::test {

namespace {

// A procedural box of density 1 (20^3 voxels of 0.05: 1 x 1 x 1 with the trilinear ramps at
// its faces), albedo 0, no lights, no ambient, background 1, seen head-on by an orthographic
// camera whose pixels all lie inside its front face.
scene::Scene absorbingBox(float densityScale) {
    scene::Scene s;
    scene::Camera cam;
    cam.type = scene::CameraType::Orthographic;
    cam.position = {0.0f, 0.0f, 4.0f};
    cam.orthoHeight = 0.8f;
    s.cameras.push_back(cam);
    scene::VolumeRef v;
    v.name = "box";
    v.procedural = "box";
    v.size = glm::vec3(1.0f);
    v.voxelSize = 0.05f;
    v.densityScale = densityScale;
    v.albedo = glm::vec3(0.0f);
    s.volumes.push_back(v);
    s.render.ambient = glm::vec3(0.0f);
    s.render.background = glm::vec3(1.0f);
    return s;
}

double meanRed(const ImageF& image) {
    double sum = 0.0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            sum += image.at(x, y, 0);
    return sum / (image.width * image.height);
}

} // namespace

TEST(IntegratorRegistry, EveryIntegratorRendersBeerLambertThroughAnAbsorbingBox) {
    openvdb::initialize();
    const auto& registry = volume::IntegratorRegistry::instance();
    ASSERT_NE(registry.find("fog-march"), nullptr);
    ASSERT_NE(registry.find("pathtraced"), nullptr);
    // Rays along -z cross 20 voxels of density 1 at 0.05: tau = 1.5 x 1.
    scene::Scene s = absorbingBox(1.5f);
    const int spp = 1024;
    s.render.pathtracedProperties = {{"spp", spp}, {"seed", 7}};
    const double expected = std::exp(-1.5);
    const int w = 4, h = 4;

    const volume::IntegratorImage march =
        registry.get("fog-march").render(s, s.cameras[0], w, h, {});
    EXPECT_EQ(march.samples, 1);
    EXPECT_TRUE(march.standardError.pixels.empty());
    // The march's midpoint rule over a piecewise-linear density: within 0.5%.
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            EXPECT_NEAR(march.radiance.at(x, y, 0), expected, 0.005 * expected) << x << "," << y;

    int passes = 0;
    const volume::IntegratorImage path =
        registry.get("pathtraced").render(s, s.cameras[0], w, h, [&](int) { return ++passes > 0; });
    EXPECT_EQ(path.samples, spp); // render.pathtraced.spp reached the tracer
    EXPECT_GT(passes, 1);         // in passes of render.pathtraced.batch (16)
    // Each sample sees the background (1) or is absorbed (0): the mean of 16 x 1024 binomial
    // samples of exp(-tau) is within 4 standard errors of it and of the march.
    const double se = std::sqrt(expected * (1.0 - expected) / (double(spp) * w * h));
    EXPECT_NEAR(meanRed(path.radiance), expected, 4.0 * se);
    EXPECT_NEAR(meanRed(path.radiance), meanRed(march.radiance), 4.0 * se + 0.005 * expected);
}

TEST(IntegratorRegistry, PathTracerPropertiesAreCheckedWhereTheSceneKeepsThem) {
    openvdb::initialize();
    scene::Scene s = absorbingBox(1.0f);
    s.render.pathtracedProperties = {{"max_bounces", 0}};
    s.render.pathtracedWhere = "box.json: /render/pathtraced";
    try {
        volume::IntegratorRegistry::instance().get("pathtraced").render(s, s.cameras[0], 2, 2, {});
        FAIL() << "max_bounces 0 was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("box.json: /render/pathtraced/max_bounces"),
                  std::string::npos)
            << e.what();
    }
}

TEST(IntegratorRegistry, UnknownNameListsTheKnownOnes) {
    try {
        volume::IntegratorRegistry::instance().get("pathtracer", "--integrator");
        FAIL() << "an unknown integrator was found";
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("--integrator: unknown integrator 'pathtracer'"), std::string::npos)
            << message;
        EXPECT_NE(message.find("fog-march"), std::string::npos) << message;
        EXPECT_NE(message.find("pathtraced"), std::string::npos) << message;
    }
}

} // namespace veil::test
