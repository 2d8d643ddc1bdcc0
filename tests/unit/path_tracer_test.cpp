// The volumetric path tracer (src/integrators/path_tracer.h) against what it did not produce:
// the adding-doubling slab solver (itself checked against Chandrasekhar's H-function and
// energy conservation), Beer-Lambert, and the single-scattering CPU fog reference; its local
// majorants against one global majorant and against the grid's own samples; its dense copy of
// a grid against OpenVDB's sampler.
#include "grid/density_grid.h"
#include "integrators/adding_doubling.h"
#include "integrators/cpu_reference.h"
#include "integrators/dense_grid.h"
#include "integrators/path_tracer.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <random>

namespace veil::test {

using volume::addingDoublingSlab;
using volume::traceSlab;

TEST(AddingDoubling, ConservesEnergyWithoutAbsorption) {
    for (double tau : {0.1, 1.0, 4.0, 16.0}) {
        const auto s = addingDoublingSlab(tau, 1.0);
        EXPECT_NEAR(s.reflectance + s.diffuseTransmittance + s.directTransmittance, 1.0, 1e-6)
            << "tau " << tau;
    }
}

TEST(AddingDoubling, ThinLayerIsSingleScattering) {
    // tau -> 0: half of the scattered fraction a tau goes up, half down.
    const double tau = 1e-4, a = 0.7;
    const auto s = addingDoublingSlab(tau, a);
    EXPECT_NEAR(s.reflectance, 0.5 * a * tau, 1e-3 * a * tau);
    EXPECT_NEAR(s.diffuseTransmittance, 0.5 * a * tau, 1e-3 * a * tau);
}

TEST(AddingDoubling, ThickSlabIsChandrasekharsPlaneAlbedo) {
    // Semi-infinite medium, normal incidence: R = 1 - H(1) sqrt(1 - a).
    for (double a : {0.5, 0.9, 0.99}) {
        const double expected = 1.0 - volume::chandrasekharH(1.0, a) * std::sqrt(1.0 - a);
        EXPECT_NEAR(addingDoublingSlab(256.0, a).reflectance, expected, 2e-5) << "albedo " << a;
    }
}

// The slab's total diffuse reflectance and transmittance against adding-doubling, to within 3
// standard errors of the Monte Carlo estimate plus 1 % of the reference value. The standard
// error used is the larger of the sample's and that of a binomial tally of the reference value
// (rare events, e.g. transmission through tau = 16, may not occur at all in n paths).
TEST(PathTracerSlab, MatchesAddingDoubling) {
    const std::uint64_t n = 8000;
    auto tolerance = [&](double se, double ref) {
        return 3.0 * std::max(se, std::sqrt(ref * (1.0 - ref) / double(n))) + 0.01 * ref;
    };
    for (double tau : {1.0, 4.0, 16.0})
        for (double a : {0.9, 0.99, 1.0}) {
            const auto ref = addingDoublingSlab(tau, a);
            const auto mc = traceSlab(tau, a, 0.0, n, 7);
            const std::string what = "tau " + std::to_string(tau) + " albedo " + std::to_string(a);
            EXPECT_NEAR(mc.reflectance, ref.reflectance,
                        tolerance(mc.reflectanceError, ref.reflectance))
                << what;
            EXPECT_NEAR(mc.diffuseTransmittance, ref.diffuseTransmittance,
                        tolerance(mc.diffuseTransmittanceError, ref.diffuseTransmittance))
                << what;
            EXPECT_NEAR(mc.directTransmittance, std::exp(-tau),
                        tolerance(mc.directTransmittanceError, std::exp(-tau)))
                << what;
        }
}

TEST(PathTracerSlab, AlbedoZeroIsBeerLambert) {
    for (double tau : {0.5, 1.0, 4.0}) {
        const auto mc = traceSlab(tau, 0.0, 0.0, 40000, 3);
        EXPECT_EQ(mc.reflectance, 0.0); // nothing scatters: exactly zero
        EXPECT_EQ(mc.diffuseTransmittance, 0.0);
        // Binomial estimate of exp(-tau): its standard error is sqrt(T (1 - T) / n).
        const double t = std::exp(-tau), se = std::sqrt(t * (1.0 - t) / 40000.0);
        EXPECT_NEAR(mc.directTransmittance, t, 4.0 * se) << "tau " << tau;
    }
}

TEST(PathTracerSlab, AlbedoOneConservesEnergy) {
    for (double tau : {1.0, 16.0}) {
        const auto mc = traceSlab(tau, 1.0, 0.6, 4000, 5);
        const double total = mc.reflectance + mc.diffuseTransmittance + mc.directTransmittance;
        // Roulette never cuts a weight of 1: every path leaves through a face with weight 1.
        EXPECT_NEAR(total, 1.0, 1e-12) << "tau " << tau;
    }
}

namespace {

// A dense box of density 1 with n^3 voxels of size h, centred at the origin.
openvdb::FloatGrid::Ptr boxGrid(int n, double h) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
    grid->transform().postTranslate(openvdb::Vec3d(-0.5 * h * (n - 1)));
    grid->tree().fill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(n - 1)), 1.0f, true);
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    return grid;
}

scene::Scene boxScene(float scale, glm::vec3 albedo) {
    scene::Scene s;
    scene::Camera cam;
    cam.type = scene::CameraType::Orthographic;
    cam.position = {0.0f, 0.0f, 4.0f};
    cam.orthoHeight = 1.6f;
    s.cameras.push_back(cam);
    scene::VolumeRef v;
    v.name = "box";
    v.densityScale = scale;
    v.albedo = albedo;
    s.volumes.push_back(v);
    s.render.ambient = glm::vec3(0.0f);
    return s;
}

} // namespace

TEST(PathTracer, AlbedoZeroBoxIsBeerLambert) {
    openvdb::initialize();
    const int n = 20;
    const double h = 0.05; // 1 x 1 x 1
    scene::Scene s = boxScene(2.0f, glm::vec3(0.0f));
    s.render.background = glm::vec3(1.0f);
    volume::PathTracerSettings settings;
    settings.spp = 400;
    const volume::VolumePathTracer tracer(s, {boxGrid(n, h)}, settings);
    // Rays along -z through the box's inner part cross n voxels: the trilinear ramps at both
    // faces add up to one voxel, so tau = scale x n x h.
    const double expected = std::exp(-2.0 * n * h);
    const auto img = tracer.render(s.cameras[0], 8, 8);
    for (int y = 2; y < 6; ++y)
        for (int x = 2; x < 6; ++x) {
            const double se = std::sqrt(expected * (1.0 - expected) / settings.spp);
            EXPECT_NEAR(img.radiance.at(x, y, 0), expected, 4.0 * se) << x << "," << y;
            EXPECT_NEAR(img.standardError.at(x, y, 0), se, 0.2 * se);
        }
}

TEST(PathTracer, SingleScatteringMatchesCpuFogReference) {
    openvdb::initialize();
    scene::Scene s = boxScene(3.0f, glm::vec3(0.9f, 0.6f, 0.3f));
    s.volumes[0].anisotropy = 0.4f;
    scene::Light sun;
    sun.direction = glm::normalize(glm::vec3(0.5f, -1.0f, -0.3f));
    sun.intensity = 2.0f;
    s.lights.push_back(sun);
    openvdb::FloatGrid::ConstPtr grid = boxGrid(16, 0.05);
    volume::PathTracerSettings settings;
    settings.spp = 256;
    settings.maxBounces = 1;
    const volume::VolumePathTracer tracer(s, {grid}, settings);
    const volume::CpuFogReference marcher(s, {grid});
    const int w = 8, hgt = 8;
    const auto pt = tracer.render(s.cameras[0], w, hgt);
    const ImageF ref = marcher.render(s.cameras[0], w, hgt, 1024);
    double sumPt = 0.0, sumRef = 0.0, var = 0.0;
    int outliers = 0;
    for (int y = 0; y < hgt; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const double a = pt.radiance.at(x, y, c), b = ref.at(x, y, c),
                             se = pt.standardError.at(x, y, c);
                sumPt += a;
                sumRef += b;
                var += se * se;
                if (std::abs(a - b) > 4.0 * se + 0.01 * b + 1e-6) ++outliers;
            }
    EXPECT_GT(sumRef, 1.0);
    EXPECT_NEAR(sumPt, sumRef, 3.0 * std::sqrt(var) + 0.005 * sumRef);
    EXPECT_LE(outliers, 1);
}

TEST(PathTracer, ProgressiveAndDeterministic) {
    openvdb::initialize();
    scene::Scene s = boxScene(3.0f, glm::vec3(0.95f));
    scene::Light sun;
    s.lights.push_back(sun);
    openvdb::FloatGrid::ConstPtr grid = boxGrid(8, 0.1);
    volume::PathTracerSettings settings;
    settings.spp = 8;
    settings.batch = 3;
    const volume::VolumePathTracer tracer(s, {grid}, settings);
    std::vector<int> passes;
    const auto a = tracer.render(s.cameras[0], 4, 4, [&](int done) {
        passes.push_back(done);
        return true;
    });
    EXPECT_EQ(passes, (std::vector<int>{3, 6, 8}));
    settings.batch = 8;
    const auto b = volume::VolumePathTracer(s, {grid}, settings).render(s.cameras[0], 4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            EXPECT_NEAR(a.radiance.at(x, y, 1), b.radiance.at(x, y, 1), 1e-6);
    const auto stopped = tracer.render(s.cameras[0], 4, 4, [](int) { return false; });
    EXPECT_EQ(stopped.samples, 3);
}

// Delta and ratio tracking against the majorant grid's cells are the estimator of one global
// majorant with fewer null collisions: the same expected image. One grid holding a dense block
// (density 1, 8 voxels wide) beside a thin one (0.02, 24 voxels), scale 12, albedo 0.9 with
// anisotropy, a sun, a sky, emission (x density), all bounces: every pixel of the two renders
// agrees within its standard errors (at most 2 of 384 values beyond 4 sigma, the sums within 3
// sigma), and the majorants are local (the thin block's cells 10x below the dense block's).
// With the walk reading a neighbouring cell's majorant the renders differ.
TEST(PathTracer, LocalMajorantsMatchOneGlobalMajorant) {
    openvdb::initialize();
    const double h = 1.0 / 16.0;
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
    grid->transform().postTranslate(openvdb::Vec3d(-1.0, -0.25, -0.25));
    grid->tree().fill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(7, 7, 7)), 1.0f, true);
    grid->tree().fill(openvdb::CoordBBox(openvdb::Coord(8, 0, 0), openvdb::Coord(31, 7, 7)), 0.02f,
                      true);
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    scene::Scene s = boxScene(12.0f, glm::vec3(0.9f, 0.8f, 0.7f));
    s.volumes[0].anisotropy = 0.5f;
    s.volumes[0].emission = glm::vec3(0.3f, 0.1f, 0.05f);
    s.cameras[0].orthoHeight = 1.2f;
    s.cameras[0].position = {0.0f, 0.3f, 4.0f};
    s.render.ambient = glm::vec3(0.3f, 0.4f, 0.6f);
    s.render.background = glm::vec3(0.1f);
    scene::Light sun;
    sun.direction = glm::normalize(glm::vec3(0.6f, -1.0f, -0.4f));
    sun.intensity = 2.0f;
    s.lights.push_back(sun);
    volume::PathTracerSettings settings;
    settings.spp = 256;
    const volume::VolumePathTracer local(s, {grid}, settings);
    settings.localMajorants = false;
    const volume::VolumePathTracer global(s, {grid}, settings);
    const volume::MajorantGrid& m = local.majorants();
    EXPECT_EQ(global.majorants().values.size(), 1u);
    EXPECT_FLOAT_EQ(global.majorants().values[0], 12.0f);
    const float dense = m.at(m.cellOf({-0.9, 0.0, 0.0})), thin = m.at(m.cellOf({0.8, 0.0, 0.0}));
    EXPECT_FLOAT_EQ(dense, 12.0f);
    EXPECT_LT(thin, 0.1f * dense);
    EXPECT_GE(thin, 12.0f * 0.02f);

    const int w = 16, hgt = 8;
    const auto a = local.render(s.cameras[0], w, hgt);
    const auto b = global.render(s.cameras[0], w, hgt);
    double sumA = 0.0, sumB = 0.0, var = 0.0;
    int outliers = 0;
    for (int y = 0; y < hgt; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const double va = a.radiance.at(x, y, c), vb = b.radiance.at(x, y, c);
                const double se2 = std::pow(a.standardError.at(x, y, c), 2) +
                                   std::pow(b.standardError.at(x, y, c), 2);
                sumA += va;
                sumB += vb;
                var += se2;
                if (std::abs(va - vb) > 4.0 * std::sqrt(se2) + 1e-6) ++outliers;
            }
    std::printf("local %.4f, global %.4f, sigma of the difference %.4f, %d beyond 4 sigma\n", sumA,
                sumB, std::sqrt(var), outliers);
    EXPECT_GT(sumB, 10.0);
    EXPECT_NEAR(sumA, sumB, 3.0 * std::sqrt(var));
    EXPECT_LE(outliers, 2);
}

// On the Disney cloud placed by a rotation and a scale (a real grid, as a scene entry places
// it): the dense copy samples exactly what OpenVDB's BoxSampler samples through the grid's tree,
// and no sample exceeds the tracer's majorant of its cell (those from the dense copy's voxels),
// near every leaf node's faces and uniformly over the box; the majorants are local.
TEST(PathTracer, DenseCopyAndMajorantsOfARealGrid) {
    openvdb::initialize();
    openvdb::FloatGrid::ConstPtr grid =
        volume::loadDensityGrid(dataDir() / "vdb-wdas-cloud/wdas_cloud_sixteenth.vdb", "density");
    scene::Scene s = boxScene(3.0f, glm::vec3(1.0f));
    s.volumes[0].transform = glm::rotate(glm::scale(glm::mat4(1.0f), glm::vec3(0.01f)), 0.5f,
                                         glm::vec3(0.3f, 1.0f, 0.2f));
    const volume::VolumePathTracer tracer(s, {grid}, volume::PathTracerSettings{});
    const volume::MajorantGrid& m = tracer.majorants();
    const glm::dmat4 toWorld(s.volumes[0].transform), toObject = glm::inverse(toWorld);
    const volume::DenseGrid dense(*grid, toObject);
    ASSERT_TRUE(dense.valid());
    auto acc = grid->getConstAccessor(), fallback = grid->getConstAccessor();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::size_t samples = 0, above = 0, differ = 0;
    double worst = 0.0;
    auto probe = [&](const openvdb::Vec3d& index) {
        const openvdb::Vec3d o = grid->transform().indexToWorld(index);
        const glm::dvec3 w(toWorld * glm::dvec4(o.x(), o.y(), o.z(), 1.0));
        if (glm::any(glm::lessThan(w, m.lo)) || glm::any(glm::greaterThan(w, m.hi))) return;
        const double v = openvdb::tools::BoxSampler::sample(acc, index);
        const double d = dense.sample(w, fallback);
        ++samples;
        if (std::abs(d - v) > 1e-6 * std::abs(v) + 1e-9) ++differ;
        const double bound = m.at(m.cellOf(w));
        if (3.0 * v > bound * (1.0 + 1e-6) + 1e-12) ++above;
        if (v > 0.0) worst = std::max(worst, 3.0 * v / std::max(bound, 1e-30));
    };
    for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) {
        const openvdb::CoordBBox b = leaf->getNodeBoundingBox();
        for (int k = 0; k < 24; ++k) {
            // A point within 2 voxels of one of the six faces, outside or inside.
            openvdb::Vec3d q;
            for (int a = 0; a < 3; ++a)
                q[a] = b.min()[a] - 2.0 + u(rng) * (b.max()[a] - b.min()[a] + 4.0);
            const int axis = k % 3;
            q[axis] = (k / 3) % 2 ? b.max()[axis] + 2.0 * u(rng) - 1.0
                                  : b.min()[axis] - 2.0 * u(rng) + 1.0;
            probe(q);
        }
    }
    const openvdb::CoordBBox b = grid->evalActiveVoxelBoundingBox();
    for (int k = 0; k < 200000; ++k)
        probe(openvdb::Vec3d(b.min().x() + u(rng) * (b.max().x() - b.min().x()),
                             b.min().y() + u(rng) * (b.max().y() - b.min().y()),
                             b.min().z() + u(rng) * (b.max().z() - b.min().z())));
    double sum = 0.0;
    for (float v : m.values)
        sum += v;
    std::printf("majorants %dx%dx%d: %zu samples, %zu above, %zu differ from the dense copy's, "
                "largest sample / majorant %.4f, mean majorant / global %.3f\n",
                m.dims.x, m.dims.y, m.dims.z, samples, above, differ, worst,
                sum / m.values.size() / tracer.majorant());
    EXPECT_GT(samples, 200000u);
    EXPECT_EQ(differ, 0u);
    EXPECT_EQ(above, 0u);
    EXPECT_GT(worst, 0.9);
    EXPECT_LT(sum / m.values.size(), 0.5 * tracer.majorant());
}

} // namespace veil::test

namespace veil::test {

// The cache's texels that surfaces read with a small footprint (scatteredLightSurfaceTexels),
// on a grid of 8 x 8 x 8 texels over [0, 4]^3 against a plane's two triangles and a box's
// twelve: a plane half a texel below the grid lists the bottom layer (64 texels) at 8 x 64
// paths, one half a texel above it the top layer, one two texels below nothing; a box a texel
// around the grid lists its outer layer (296 texels: the inner 6 x 6 x 6 lie farther than a
// texel from its faces), their extra paths capped at the bake's own (2 x 64, not 8 x 64); the
// factor 1 lists nothing.
TEST(ScatteredLightSurfaceTexels, ListsTheTexelsWithinATexelOfASurface) {
    scene::Scene s;
    s.render.fogScatteredLightSamples = 64;
    s.render.fogScatteredLightSurfaceFactor = 8;
    s.meshes.push_back(scene::makePlane({8.0f, 8.0f})); // the xz plane, normal +y
    s.meshes.push_back(scene::makeBox({5.0f, 5.0f, 5.0f}));
    const glm::dvec3 lo(0.0), hi(4.0);
    const glm::ivec3 dims(8);
    const auto at = [&](std::uint32_t mesh, float y) {
        scene::Object o;
        o.mesh = mesh;
        o.transform = glm::translate(glm::mat4(1.0f), glm::vec3(2.0f, y, 2.0f));
        s.objects = {o};
        return volume::scatteredLightSurfaceTexels(s, lo, hi, dims);
    };
    const auto layers = [](const volume::ScatteredLightSurface& t) {
        std::vector<int> y;
        for (std::uint32_t i : t.texels)
            y.push_back(int(i / 8 % 8));
        return y;
    };
    const volume::ScatteredLightSurface below = at(0, -0.25f);
    EXPECT_EQ(below.texels.size(), 64u);
    EXPECT_EQ(layers(below), std::vector<int>(64, 0));
    EXPECT_EQ(below.samples, 512);
    const volume::ScatteredLightSurface above = at(0, 4.25f);
    EXPECT_EQ(layers(above), std::vector<int>(64, 7));
    EXPECT_TRUE(at(0, -1.0f).texels.empty());
    const volume::ScatteredLightSurface around = at(1, 2.0f);
    EXPECT_EQ(around.texels.size(), 296u);
    EXPECT_EQ(around.samples, 128);
    s.render.fogScatteredLightSurfaceFactor = 1;
    EXPECT_TRUE(at(0, -0.25f).texels.empty());
}

} // namespace veil::test
