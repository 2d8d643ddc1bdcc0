// Solid (XOR) voxelization against the CPU parity reference, local vs uniform slicing on a
// scene with a large depth range, and the GLSL slice-map queries against their C++ twins.
#include "gl_fixture.h"

#include "gpu/shader.h"
#include "scene/mesh.h"
#include "shaders/common/bindings.h"
#include "voxelize/cpu_voxelizer.h"
#include "voxelize/gpu_voxelizer.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstring>
#include <random>

namespace veil::test {

using namespace veil::voxelize;

namespace {

class VoxelizeSolidLocalGLTest : public GlTest {};

// Bound: the GPU and CPU both take crossings at column centres, so they may differ only where
// a crossing lies within float rounding of a slice centre or a column centre lies on an edge:
// every mismatch must be a cell of the exact surface shell, and mismatches <= 0.5% of the
// solid cells.
TEST_F(VoxelizeSolidLocalGLTest, SolidMatchesCpuParity) {
    GpuVoxelizer vox(info());
    const glm::mat4 rot = glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(3, 1, 2)));
    const std::pair<const char*, Triangles> shapes[] = {
        {"sphere", fromMesh(scene::makeSphere(1.0f, 48, 24))},
        {"box", fromMesh(scene::makeBox({1.6f, 1.0f, 0.7f}), rot)}};
    for (const auto& [name, tris] : shapes) {
        vox.upload(tris);
        for (int res : {32, 64, 128}) {
            SliceMap ref = makeOrthoGrid({-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}, res, res, res);
            SliceMap shell = ref, got = ref;
            voxelizeSolidCpu(tris, ref);
            voxelizeSurfaceCpu(tris, shell);
            vox.voxelize(got, {Method::Raster, true, false});
            VEIL_EXPECT_NO_GL_ERROR();
            std::uint64_t mismatch = 0, outsideShell = 0;
            for (std::size_t i = 0; i < ref.words.size(); ++i) {
                const std::uint32_t d = ref.words[i] ^ got.words[i];
                mismatch += std::popcount(d);
                outsideShell += std::popcount(d & ~shell.words[i]);
            }
            std::printf("solid %-6s res %3d: cpu %8llu gpu %8llu mismatches %llu\n", name, res,
                        (unsigned long long)ref.countSet(), (unsigned long long)got.countSet(),
                        (unsigned long long)mismatch);
            EXPECT_EQ(outsideShell, 0u) << name << " " << res;
            EXPECT_LE(double(mismatch), 0.005 * double(ref.countSet())) << name << " " << res;
        }
    }
}

// 1300 slices need two geometry passes of 1024 (8 RGBA32UI targets): surface (conservative:
// zero missed vs the exact overlap) and solid (zero mismatches vs CPU parity) across passes.
TEST_F(VoxelizeSolidLocalGLTest, MoreThan1024SlicesTakeSeveralPasses) {
    const Triangles sphere = fromMesh(scene::makeSphere(1.0f, 32, 16));
    GpuVoxelizer vox(info());
    vox.upload(sphere);
    SliceMap ref = makeOrthoGrid({-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}, 20, 20, 1300);
    SliceMap got = ref;
    voxelizeSurfaceCpu(sphere, ref);
    vox.voxelize(got, {Method::Conservative, false, false});
    EXPECT_NE(vox.path().find("2 geometry passes"), std::string::npos) << vox.path();
    std::uint64_t missed = 0;
    for (std::size_t i = 0; i < ref.words.size(); ++i)
        missed += std::popcount(ref.words[i] & ~got.words[i]);
    EXPECT_EQ(missed, 0u);
    EXPECT_GT(got.countSet(), ref.countSet() / 2);
    voxelizeSolidCpu(sphere, ref);
    vox.voxelize(got, {Method::Raster, true, false});
    EXPECT_EQ(got.words, ref.words);
    VEIL_EXPECT_NO_GL_ERROR();
}

// Two spheres of radius 0.5, 40 units apart along the view axis (z) and side by side in x:
// uniform slicing spends 64 slices on 41 units of depth; local slicing spends them on each
// column's own [near, far] [Eisemann06 sec. 2.2].
TEST_F(VoxelizeSolidLocalGLTest, LocalSlicingResolvesMoreDepth) {
    Triangles tris;
    tris.append(scene::makeSphere(0.5f, 48, 24),
                glm::translate(glm::mat4(1.0f), glm::vec3(-0.6f, 0.0f, 0.0f)));
    tris.append(scene::makeSphere(0.5f, 48, 24),
                glm::translate(glm::mat4(1.0f), glm::vec3(0.6f, 0.0f, 40.0f)));
    GpuVoxelizer vox(info());
    vox.upload(tris);
    const glm::dvec3 lo(-1.2, -0.6, -0.6), hi(1.2, 0.6, 40.6);
    double volume[2], slicesPerColumn[2];
    for (int local = 0; local < 2; ++local) {
        SliceMap solid = makeOrthoGrid(lo, hi, 96, 48, 64);
        vox.voxelize(solid, {Method::Raster, true, local == 1});
        SliceMap surface = makeOrthoGrid(lo, hi, 96, 48, 64);
        vox.voxelize(surface, {Method::Conservative, false, local == 1});
        EXPECT_EQ(surface.local(), local == 1);
        const double area = (2.4 / 96) * (1.2 / 48);
        double v = 0.0, slices = 0.0;
        int columns = 0;
        for (int y = 0; y < solid.height; ++y)
            for (int x = 0; x < solid.width; ++x) {
                v += solid.thickness(x, y) * area;
                const int n = surface.countOccupied(x, y, 0, surface.slices - 1);
                if (n > 0) slices += n, ++columns;
            }
        volume[local] = v;
        slicesPerColumn[local] = slices / columns;
    }
    const double exact = 2.0 * 4.0 / 3.0 * M_PI * 0.125;
    std::printf("two spheres: volume uniform %.4f local %.4f (tessellated ~%.4f); surface slices "
                "per column uniform %.2f local %.2f\n",
                volume[0], volume[1], exact, slicesPerColumn[0], slicesPerColumn[1]);
    EXPECT_LT(std::abs(volume[1] - exact), 0.04 * exact);
    EXPECT_LT(std::abs(volume[1] - exact), 0.5 * std::abs(volume[0] - exact));
    EXPECT_GT(slicesPerColumn[1], 5.0 * slicesPerColumn[0]);
}

// Perspective grid camera (slices equal in eye depth), uniform and local: a conservative
// voxelization must contain every point of every triangle, checked at the vertices,
// centroids and edge midpoints of a torus through SliceMap::occupied (the cell holding the
// point is set).
TEST_F(VoxelizeSolidLocalGLTest, PerspectiveConservativeContainsTheSurface) {
    const Triangles torus = fromMesh(scene::makeTorus(1.0f, 0.35f, 40, 20),
                                     glm::rotate(glm::mat4(1.0f), 0.9f, glm::vec3(1, 0, 0)));
    GpuVoxelizer vox(info());
    vox.upload(torus);
    for (bool local : {false, true}) {
        SliceMap grid =
            makePerspectiveGrid({0.3, 0.4, 5.0}, {0, 0, 0}, {0, 1, 0}, 40.0, 3.0, 7.0, 64, 64, 96);
        vox.voxelize(grid, {Method::Conservative, false, local});
        int outside = 0, missed = 0, checked = 0;
        for (std::size_t t = 0; t < torus.count(); ++t) {
            const glm::dvec3 a(torus.vertices[3 * t]), b(torus.vertices[3 * t + 1]),
                c(torus.vertices[3 * t + 2]);
            for (const glm::dvec3& p : {a, (a + b + c) / 3.0, 0.5 * (a + b), 0.5 * (b + c)}) {
                int x, y, s;
                if (!grid.locate(p, x, y, s)) {
                    ++outside;
                    continue;
                }
                ++checked;
                missed += grid.get(x, y, s) ? 0 : 1;
            }
        }
        std::printf("perspective %s: %d surface points checked, %d missed, %d outside, %llu set\n",
                    local ? "local" : "uniform", checked, missed, outside,
                    (unsigned long long)grid.countSet());
        EXPECT_EQ(outside, 0);
        EXPECT_EQ(missed, 0);
    }
}

TEST_F(VoxelizeSolidLocalGLTest, GlslQueriesMatchCpp) {
    GpuVoxelizer vox(info());
    const Triangles torus = fromMesh(scene::makeTorus(1.0f, 0.35f, 32, 16));
    vox.upload(torus);
    gpu::Program probe(gpu::ProgramDesc::compute("voxelize/query_probe.comp"));
    for (bool local : {false, true}) {
        SliceMap grid = makeOrthoGrid({-1.5, -1.5, -0.5}, {1.5, 1.5, 0.5}, 40, 40, 70);
        vox.voxelize(grid, {Method::Conservative, false, local});
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(-1.6f, 1.6f);
        std::vector<glm::vec4> points;
        std::vector<glm::ivec4> cols;
        for (int i = 0; i < 512; ++i) {
            points.emplace_back(u(rng), u(rng), 0.4f * u(rng), 1.0f);
            const int s0 = int(rng() % 70);
            cols.emplace_back(int(rng() % 40), int(rng() % 40), s0, s0 + int(rng() % 50));
        }
        gpu::Buffer pb, cb, ob;
        pb.setStorage(std::span<const glm::vec4>(points));
        cb.setStorage(std::span<const glm::ivec4>(cols));
        ob.setStorage(points.size() * 6 * 4, nullptr);
        pb.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_AXIS0);
        cb.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_AXIS0 + 1);
        ob.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_AXIS0 + 2);
        vox.bindSliceMap(probe, grid);
        probe.set("uProbeCount", int(points.size()));
        probe.use();
        glDispatchCompute(8, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<int> out(points.size() * 6);
        glGetNamedBufferSubData(ob.id(), 0, GLsizeiptr(out.size() * 4), out.data());
        VEIL_EXPECT_NO_GL_ERROR();
        int occupiedHits = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const glm::dvec3 p(points[i]);
            const glm::ivec4 c = cols[i];
            int x, y, s;
            const bool inside = grid.locate(p, x, y, s);
            // A point within float rounding of a cell plane may land in the neighbour cell.
            if (inside == (out[6 * i + 4] >= 0) && (!inside || s == out[6 * i + 4])) {
                EXPECT_EQ(out[6 * i], grid.occupied(p) ? 1 : 0) << i;
                occupiedHits += out[6 * i];
            }
            EXPECT_EQ(out[6 * i + 1], grid.countOccupied(c.x, c.y, c.z, c.w)) << i;
            EXPECT_EQ(out[6 * i + 2], grid.firstOccupied(c.x, c.y)) << i;
            EXPECT_EQ(out[6 * i + 3], grid.lastOccupied(c.x, c.y)) << i;
            float th;
            std::memcpy(&th, &out[6 * i + 5], 4);
            EXPECT_NEAR(th, grid.thickness(c.x, c.y), 1e-4 + 1e-4 * grid.thickness(c.x, c.y));
        }
        EXPECT_GT(occupiedHits, 0) << "no probe hit the torus: the test would prove nothing";
    }
}

} // namespace
} // namespace veil::test
