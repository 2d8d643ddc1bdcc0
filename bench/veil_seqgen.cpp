// veil-seqgen: writes a heavy VDB sequence to measure frame ranges with (veil-seqbench,
// `veil render --frames`): a procedural cloud of about N active voxels per frame, one .vdb file
// per frame, whose shape changes from frame to frame. The cloud is a ball whose radius is
// modulated by value noise over the direction (so the silhouette billows) and whose density is
// value noise fBm inside it, both drifting with the frame; every voxel inside is active. The
// radius is chosen so that the ball holds N voxels; the count a frame really has is printed.
//
//   veil-seqgen --voxels 30M --frames 1-24 -o /tmp/heavy/cloud_#.vdb
//
// Each file is written atomically (temporary file, then rename); the folder must exist.
#include "base/error.h"
#include "grid/density_grid.h"
#include "scene/animation.h"
#include "scene/timeline.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

void usage() {
    std::puts("usage: veil-seqgen --voxels N --frames A-B[:S] -o DIR/name_#.vdb\n"
              "  --voxels N   active voxels per frame (suffix K or M: 100K, 30M; 1K..100M)\n"
              "  --frames     the frames to write (one file each)\n"
              "  -o           output pattern with a frame number (#, ####, %04d, $F4)");
}

// Smooth value noise in [0, 1] on the integer lattice, hashed per seed.
float hash3(int x, int y, int z, std::uint32_t seed) {
    std::uint32_t h = seed * 0x9E3779B1u ^ std::uint32_t(x) * 0x85EBCA77u ^
                      std::uint32_t(y) * 0xC2B2AE3Du ^ std::uint32_t(z) * 0x27D4EB2Fu;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    h *= 0x297A2D39u;
    h ^= h >> 15;
    return float(h & 0xFFFFFFu) / float(0xFFFFFFu);
}

float noise(float x, float y, float z, std::uint32_t seed) {
    const float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    const int ix = int(fx), iy = int(fy), iz = int(fz);
    auto s = [](float t) { return t * t * (3.0f - 2.0f * t); };
    const float tx = s(x - fx), ty = s(y - fy), tz = s(z - fz);
    float c[2][2];
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy) {
            const float a = hash3(ix, iy + dy, iz + dz, seed);
            const float b = hash3(ix + 1, iy + dy, iz + dz, seed);
            c[dz][dy] = a + (b - a) * tx;
        }
    const float y0 = c[0][0] + (c[0][1] - c[0][0]) * ty;
    const float y1 = c[1][0] + (c[1][1] - c[1][0]) * ty;
    return y0 + (y1 - y0) * tz;
}

float fbm(float x, float y, float z, std::uint32_t seed) {
    float sum = 0.0f, amp = 0.5f, norm = 0.0f;
    for (int o = 0; o < 4; ++o) {
        sum += amp * noise(x, y, z, seed + std::uint32_t(o));
        norm += amp;
        x *= 2.03f, y *= 2.03f, z *= 2.03f;
        amp *= 0.5f;
    }
    return sum / norm;
}

// The cloud of frame `frame` for a ball of radius `r` voxels.
openvdb::FloatGrid::Ptr cloud(double r, int frame) {
    const int extent = int(std::ceil(r * 1.2)) + 1;
    const float t = 0.05f * float(frame);
    tbb::enumerable_thread_specific<openvdb::FloatGrid::Ptr> parts(
        [] { return openvdb::FloatGrid::create(0.0f); });
    tbb::parallel_for(tbb::blocked_range<int>(-extent, extent + 1), [&](const auto& zs) {
        openvdb::FloatGrid::Ptr& g = parts.local();
        auto acc = g->getAccessor();
        for (int z = zs.begin(); z != zs.end(); ++z)
            for (int y = -extent; y <= extent; ++y)
                for (int x = -extent; x <= extent; ++x) {
                    const float d = std::sqrt(float(x * x + y * y + z * z));
                    if (d > float(extent)) continue;
                    // The radius in this direction: 1 +- 0.2 of r, billowing with the frame.
                    const float inv = d > 0.0f ? 1.0f / d : 0.0f;
                    const float bump = noise(2.0f * float(x) * inv + t, 2.0f * float(y) * inv,
                                             2.0f * float(z) * inv - t, 7u);
                    const float radius = float(r) * (0.8f + 0.4f * bump);
                    if (d > radius) continue;
                    const float q = 6.0f / float(r);
                    const float v =
                        fbm(float(x) * q + t, float(y) * q, float(z) * q + 0.5f * t, 11u);
                    // Thinner toward the edge; never 0 inside (every voxel stays active).
                    const float edge = 1.0f - d / radius;
                    acc.setValue(openvdb::Coord(x, y, z), 0.02f + v * std::min(1.0f, 4.0f * edge));
                }
    });
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    for (openvdb::FloatGrid::Ptr& p : parts)
        grid->tree().merge(p->tree());
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    return grid;
}

double parseCount(const std::string& s) {
    std::size_t used = 0;
    double v = std::stod(s, &used);
    const std::string unit = s.substr(used);
    if (unit == "K" || unit == "k")
        v *= 1e3;
    else if (unit == "M" || unit == "m")
        v *= 1e6;
    else if (!unit.empty())
        throw std::invalid_argument(s);
    return v;
}

} // namespace

int main(int argc, char** argv) {
    using namespace veil;
    double voxels = 0.0;
    std::string frames, output;
    for (int i = 1; i < argc; ++i) {
        const std::string s = argv[i];
        if ((s == "--voxels" || s == "--frames" || s == "-o") && i + 1 >= argc) {
            usage();
            return 2;
        }
        try {
            if (s == "--voxels")
                voxels = parseCount(argv[++i]);
            else if (s == "--frames")
                frames = argv[++i];
            else if (s == "-o")
                output = argv[++i];
            else if (s == "-h" || s == "--help") {
                usage();
                return 0;
            } else {
                usage();
                return 2;
            }
        } catch (const std::exception&) {
            std::fprintf(stderr, "veil-seqgen: bad value for %s\n", s.c_str());
            return 2;
        }
    }
    if (!(voxels >= 1e3 && voxels <= 1e8) || frames.empty() || output.empty()) {
        usage();
        return 2;
    }
    try {
        const std::optional<scene::FilePattern> pattern = scene::parseFilePattern(output);
        VEIL_CHECK(pattern, "output '{}' has no frame pattern (name_#.vdb, name_####.vdb)", output);
        const fs::path dir = fs::path(output).parent_path();
        std::error_code ec;
        VEIL_CHECK(dir.empty() || fs::is_directory(dir, ec), "output folder '{}' does not exist",
                   dir.string());
        const std::vector<int> list = scene::parseFrameRange(frames).frames();
        // A ball of N voxels: N = 4/3 pi r^3 on average over the radius modulation (0.8..1.2).
        const double r = std::cbrt(voxels / (4.0 / 3.0 * M_PI * 1.04));
        openvdb::initialize();
        const auto start = Clock::now();
        for (std::size_t i = 0; i < list.size(); ++i) {
            const openvdb::FloatGrid::Ptr g = cloud(r, list[i]);
            const fs::path file = pattern->fileFor(list[i]);
            volume::saveGrids(file, {g});
            const double s = std::chrono::duration<double>(Clock::now() - start).count();
            std::printf("frame %d (%zu/%zu): %llu active voxels -> %s; %.1f s, about %.0f s "
                        "left\n",
                        list[i], i + 1, list.size(), (unsigned long long)g->activeVoxelCount(),
                        file.string().c_str(), s, s / double(i + 1) * double(list.size() - i - 1));
            std::fflush(stdout);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "veil-seqgen: %s\n", e.what());
        return 1;
    }
}
