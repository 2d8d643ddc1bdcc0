// veil-voxbench: voxelizes a mesh N times per method and reports median/min/max GPU times
// (GL_TIME_ELAPSED where the driver has it, else glFinish + CPU clock), next to
// openvdb::tools::meshToUnsignedDistanceField at the same voxel size (CPU, TBB threads).
// Links the core and veil_voxelize only (no OpenImageIO, no VTK) so it travels to the GPU
// machine. --check also compares every method's voxels with the CPU exact overlap
// (missed / extra / IoU), e.g. to check the GL_NV_conservative_raster path on the GPU.
#include "base/atomic_file.h"
#include "base/error.h"
#include "gpu/context.h"
#include "scene/scene.h"
#include "voxelize/cpu_voxelizer.h"
#include "voxelize/gpu_voxelizer.h"
#include "voxelize/triangles.h"

#include <nlohmann/json.hpp>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void usage() {
    std::puts("usage: veil-voxbench <mesh.obj|scene.json> [--res N]... [--slices N]... [--runs N] "
              "[--warmup N]\n"
              "                     [--methods raster,conservative,three-axis,compute]\n"
              "                     [--no-openvdb] [--check] [--json out.json]");
}

} // namespace

int main(int argc, char** argv) try {
    using namespace veil::voxelize;
    std::string input, jsonPath, methodList = "raster,conservative,three-axis,compute";
    std::vector<int> resolutions;
    std::vector<int> sliceCounts; // empty: as many slices as columns per side (cubic voxels)
    int runs = 20, warmup = 3;
    bool openvdbToo = true, check = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            VEIL_CHECK(i + 1 < argc, "{} needs a value", a);
            return argv[++i];
        };
        if (a == "--res")
            resolutions.push_back(std::stoi(next()));
        else if (a == "--slices")
            sliceCounts.push_back(std::stoi(next()));
        else if (a == "--runs")
            runs = std::max(1, std::stoi(next()));
        else if (a == "--warmup")
            warmup = std::max(0, std::stoi(next()));
        else if (a == "--methods")
            methodList = next();
        else if (a == "--no-openvdb")
            openvdbToo = false;
        else if (a == "--check")
            check = true;
        else if (a == "--json")
            jsonPath = next();
        else if (a == "-h" || a == "--help")
            return usage(), 0;
        else if (input.empty())
            input = a;
        else
            throw veil::Error(fmt::format("unexpected argument '{}'", a));
    }
    if (input.empty()) return usage(), 2;
    if (resolutions.empty()) resolutions = {128, 256, 512};
    std::vector<Method> methods;
    for (std::size_t p = 0; p <= methodList.size();) {
        const std::size_t q = std::min(methodList.find(',', p), methodList.size());
        methods.push_back(parseMethod(methodList.substr(p, q - p)));
        p = q + 1;
    }
    Triangles tris;
    if (std::filesystem::path(input).extension() == ".json")
        tris = flattenScene(veil::scene::loadScene(input));
    else
        for (const auto& m : veil::scene::loadMeshFile(input))
            tris.append(m.mesh, glm::mat4(1.0f));
    glm::vec3 lo, hi;
    tris.bounds(lo, hi);

    veil::gpu::HeadlessContext context;
    GpuVoxelizer vox(context.info());
    vox.upload(tris);
    nlohmann::json report;
    report["input"] = input;
    report["triangles"] = tris.count();
    report["renderer"] = context.info().renderer;
    report["timer"] = context.info().softwareRenderer ? "glFinish + CPU clock" : "GL_TIME_ELAPSED";
    nlohmann::json rows = nlohmann::json::array();
    std::printf("%zu triangles, %s\n", tris.count(), context.info().renderer.c_str());
    if (sliceCounts.empty()) sliceCounts.push_back(0);
    // res x res columns, `slices` slices over the same cube (0: res slices, cubic voxels).
    auto makeGrid = [&](int res, int slices) {
        if (slices <= 0) return makeFittedCubeGrid(lo, hi, res);
        const SliceMap cube = makeFittedCubeGrid(lo, hi, res);
        glm::dvec3 glo, ghi;
        gridBounds(cube, glo, ghi);
        return makeOrthoGrid(glo, ghi, res, res, slices);
    };
    for (int res : resolutions)
        for (int slicesArg : sliceCounts) {
            const int slices = slicesArg > 0 ? slicesArg : res;
            SliceMap reference{};
            if (check) {
                reference = makeGrid(res, slicesArg);
                voxelizeSurfaceCpu(tris, reference);
            }
            for (Method m : methods) {
                SliceMap grid = makeGrid(res, slicesArg);
                std::vector<double> ms;
                std::uint64_t set = 0;
                for (int r = 0; r < warmup + runs; ++r) {
                    vox.voxelize(grid, {m, false, false});
                    if (r >= warmup) ms.push_back(vox.milliseconds());
                    set = grid.countSet();
                }
                const double med = median(ms);
                nlohmann::json checked;
                if (check) {
                    std::uint64_t missed = 0, extra = 0;
                    for (std::size_t i = 0; i < grid.words.size(); ++i) {
                        missed += std::popcount(reference.words[i] & ~grid.words[i]);
                        extra += std::popcount(grid.words[i] & ~reference.words[i]);
                    }
                    const double ref = double(reference.countSet());
                    const double iou = (ref - double(missed)) / (ref + double(extra));
                    std::printf(
                        "  check vs CPU exact overlap: missed %llu extra %llu IoU %.4f (%s)\n",
                        (unsigned long long)missed, (unsigned long long)extra, iou,
                        vox.path().c_str());
                    checked = {{"missed", missed}, {"extra", extra}, {"iou", iou}};
                }
                std::printf(
                    "res %4d slices %4d %-13s median %9.3f ms  min %9.3f  max %9.3f  set %llu\n",
                    res, slices, methodName(m).c_str(), med,
                    *std::min_element(ms.begin(), ms.end()),
                    *std::max_element(ms.begin(), ms.end()), (unsigned long long)set);
                rows.push_back({{"res", res},
                                {"slices", slices},
                                {"method", methodName(m)},
                                {"path", vox.path()},
                                {"median_ms", med},
                                {"min_ms", *std::min_element(ms.begin(), ms.end())},
                                {"max_ms", *std::max_element(ms.begin(), ms.end())},
                                {"voxels", set},
                                {"check", checked}});
            }
            // OpenVDB at the column spacing (its voxels are cubes), once per resolution.
            if (openvdbToo && slicesArg == sliceCounts.front()) {
                openvdb::initialize();
                const SliceMap grid = makeFittedCubeGrid(lo, hi, res);
                glm::dvec3 glo, ghi;
                gridBounds(grid, glo, ghi);
                const double voxel = (ghi.x - glo.x) / res;
                auto xform = openvdb::math::Transform::createLinearTransform(voxel);
                std::vector<openvdb::Vec3s> points;
                std::vector<openvdb::Vec3I> faces;
                for (const glm::vec3& v : tris.vertices)
                    points.emplace_back(v.x, v.y, v.z);
                for (std::size_t t = 0; t < tris.count(); ++t)
                    faces.emplace_back(3 * t, 3 * t + 1, 3 * t + 2);
                std::vector<double> ms;
                openvdb::Index64 active = 0;
                for (int r = 0; r < std::max(1, runs / 4); ++r) {
                    const auto t0 = std::chrono::steady_clock::now();
                    auto udf = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(
                        *xform, points, faces, std::vector<openvdb::Vec4I>(), 1.0f);
                    ms.push_back(std::chrono::duration<double, std::milli>(
                                     std::chrono::steady_clock::now() - t0)
                                     .count());
                    active = udf->activeVoxelCount();
                }
                std::printf("res %4d %-13s median %9.3f ms  (CPU, band 1 voxel, %llu active)\n",
                            res, "openvdb-udf", median(ms), (unsigned long long)active);
                rows.push_back({{"res", res},
                                {"method", "openvdb meshToUnsignedDistanceField (CPU)"},
                                {"median_ms", median(ms)},
                                {"voxels", active}});
            }
        }
    report["results"] = rows;
    if (!jsonPath.empty())
        veil::writeFileAtomically(jsonPath, [&](const std::filesystem::path& tmp) {
            std::ofstream(tmp) << report.dump(2) << "\n";
        });
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "veil-voxbench: error: %s\n", e.what());
    return 1;
}
