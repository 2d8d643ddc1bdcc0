// `veil info <file>`: what a scene (.json) or OpenVDB (.vdb) file holds.
#include "app/commands.h"

#include "grid/vdb_info.h"

#include "base/error.h"
#include "base/suggest.h"
#include "base/text.h"
#include "fog/gpu_volume.h"
#include "grid/density_grid.h"
#include "grid/vdb_file.h"
#include "scene/scene.h"
#include "scene/scene_document.h"
#include "scene/timeline.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Count.h>

#include <iostream>
#include <memory>
#include <numeric>
#include <set>

#include <fmt/ranges.h>

namespace veil::app {

namespace fs = std::filesystem;

namespace {

const char* lightTypeName(scene::LightType t) {
    switch (t) {
    case scene::LightType::Directional:
        return "directional";
    case scene::LightType::Spot:
        return "spot";
    case scene::LightType::Point:
        return "point";
    }
    return "?";
}

// The first 40 frames, then the count of all (`total`: frames.size() when not given).
std::string frameList(const std::vector<int>& frames, long long total = -1) {
    if (total < 0) total = (long long)frames.size();
    std::string out;
    for (std::size_t i = 0; i < frames.size() && i < 40; ++i)
        out += (i ? " " : "") + std::to_string(frames[i]);
    if (total > 40) out += fmt::format(" ... ({} in all)", total);
    return out;
}

// A file sequence: its range, the files found and missing, per frame the grids (names, active
// voxels of `grid`), and the union of `grid`'s world bounds over the frames. With `required`,
// a grid that no file of the range holds is an error (before anything is printed).
void printSequence(const scene::FileSequence& s, const std::string& grid, const char* indent,
                   bool required = false) {
    const std::vector<int> found = scene::existingFrames(s.pattern);
    const std::vector<int> missing = scene::missingFrames(s, 40);
    struct Row {
        int frame;
        std::string names, voxels = "-";
    };
    std::vector<Row> rows;
    long long inRange = 0;
    openvdb::BBoxd bounds;
    bool any = false, holds = false;
    std::set<std::string> allNames;
    for (int f : found) { // the files that exist, in the range and on its steps
        if (f < s.first || f > s.last || ((long long)f - s.first) % s.step != 0) continue;
        ++inRange;
        const fs::path file = s.pattern.fileFor(f);
        Row row{f, {}};
        try {
            for (const volume::GridSummary& g : volume::listGrids(file)) {
                row.names += (row.names.empty() ? "" : ", ") + g.name;
                allNames.insert(g.name);
                if (g.name == grid && row.voxels == "-") {
                    holds = true;
                    row.voxels = fmt::format("{}", g.activeVoxels);
                    if (g.activeVoxels > 0) {
                        if (!any) bounds = g.worldBounds;
                        bounds.expand(g.worldBounds);
                        any = true;
                    }
                }
            }
        } catch (const Error& e) {
            row.names = std::string("unreadable: ") + e.what();
        }
        rows.push_back(std::move(row));
    }
    if (required && !holds) {
        const std::vector<std::string> names(allNames.begin(), allNames.end());
        throw Error(fmt::format("--grid '{}': no file of the sequence '{}' holds a grid of that "
                                "name{} (grids: {})",
                                grid, s.pattern.written, didYouMean(grid, names),
                                names.empty() ? std::string("none readable")
                                              : fmt::format("{}", fmt::join(names, ", "))));
    }
    const long long missingCount = s.count() - inRange;
    std::cout << fmt::format("{}sequence   {}\n{}  range    {}-{} step {} ({} frames{}), {} "
                             "files found{}\n",
                             indent, s.pattern.written, indent, s.first, s.last, s.step, s.count(),
                             s.framesGiven ? ", as given" : ", from the files", found.size(),
                             found.empty() ? std::string()
                                           : fmt::format(" ({}-{})", found.front(), found.back()));
    std::cout << indent << "  missing  "
              << (missing.empty() ? "none" : frameList(missing, missingCount)) << "\n";
    for (const Row& row : rows)
        std::cout << fmt::format("{}  frame {:<5} {} ('{}': {} active voxels)\n", indent, row.frame,
                                 row.names, grid, row.voxels);
    if (any)
        std::cout << fmt::format("{}  bounds   ({:.4g} {:.4g} {:.4g})..({:.4g} {:.4g} {:.4g}) "
                                 "world, union of '{}' over the frames\n",
                                 indent, bounds.min().x(), bounds.min().y(), bounds.min().z(),
                                 bounds.max().x(), bounds.max().y(), bounds.max().z(), grid);
}

void printScene(const fs::path& path) {
    const scene::AnimatedScene animated = scene::loadAnimatedScene(path);
    const scene::Scene& s = animated.scene;
    const scene::Timeline& t = animated.timeline;
    std::size_t triangles = 0;
    for (const auto& o : s.objects)
        triangles += s.meshes.at(o.mesh).triangleCount();
    std::size_t transparent = 0;
    for (const auto& o : s.objects)
        transparent += s.materials.at(o.material).isTransparent();
    glm::vec3 lo, hi;
    s.bounds(lo, hi);
    std::cout << "scene " << path.string() << "\n"
              << "  render     " << s.render.width << "x" << s.render.height << ", oit "
              << s.render.oit << ", tonemap " << s.render.tonemap << ", seed " << s.render.seed
              << "\n"
              << "  objects    " << s.objects.size() << " (" << transparent << " transparent), "
              << triangles << " triangles, " << s.materials.size() << " materials\n"
              << fmt::format("  bounds     ({:.3g}, {:.3g}, {:.3g}) .. ({:.3g}, {:.3g}, {:.3g})\n",
                             lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
    for (const auto& c : s.cameras)
        std::cout << "  camera     " << c.name << " ("
                  << (c.type == scene::CameraType::Perspective ? "perspective" : "orthographic")
                  << ")\n";
    for (const auto& l : s.lights)
        std::cout << "  light      " << (l.name.empty() ? "-" : l.name) << " ("
                  << lightTypeName(l.type) << ", intensity " << l.intensity
                  << (l.castShadows ? ", shadows" : "") << ")\n";
    static const char* outside[] = {"hold", "loop", "blank"};
    for (std::size_t i = 0; i < s.volumes.size(); ++i) {
        const scene::VolumeRef& v = s.volumes[i];
        const std::string name = v.name.empty() ? "-" : v.name;
        const std::string optics =
            fmt::format("density_scale {:.4g}, albedo ({:.3g} {:.3g} {:.3g}), g {:.3g}",
                        v.densityScale, v.albedo.x, v.albedo.y, v.albedo.z, v.anisotropy);
        if (v.procedural == "homogeneous")
            std::cout << "  volume     " << name << " (homogeneous haze filling the scene, "
                      << optics << ")\n";
        else if (!v.procedural.empty())
            std::cout << "  volume     " << name << " (procedural " << v.procedural << ", size "
                      << fmt::format("{:.4g} {:.4g} {:.4g}", v.size.x, v.size.y, v.size.z) << ", "
                      << optics << ")\n";
        else
            std::cout << "  volume     " << name << " (" << v.path.string() << " grid '" << v.grid
                      << "', " << optics << ")\n";
        if (const auto& q = t.volumes[i]) {
            std::cout << fmt::format("             frame_offset {}, before {}, after {}, "
                                     "missing {}\n",
                                     q->frameOffset, outside[int(q->before)],
                                     outside[int(q->after)], q->holdMissing ? "hold" : "error");
            printSequence(*q, v.grid, "             ");
        }
    }
    if (t.animated()) {
        const scene::FrameRange r = scene::sceneFrameRange(t);
        std::cout << fmt::format("  time       frames {}-{}{}, {} fps, still frame {}\n", r.first,
                                 r.last, t.time.rangeGiven ? " (time.frame_range)" : "", t.time.fps,
                                 scene::defaultFrame(t));
        for (std::size_t i = 0; i < s.cameras.size(); ++i) {
            const scene::CameraAnimation& a = t.cameras[i];
            if (a.animated())
                std::cout << fmt::format(
                    "  animated   camera {}: {} position, {} target, {} fov keys{}\n",
                    s.cameras[i].name, a.position.frames.size(), a.target.frames.size(),
                    a.fov.frames.size(),
                    a.turntable.enabled ? fmt::format(", turntable {} degrees per {} frames",
                                                      a.turntable.degrees, a.turntable.frames)
                                        : "");
        }
    }
}

std::string formatBytes(std::size_t bytes) {
    if (bytes >= (std::size_t(1) << 20)) return fmt::format("{:.2f} MiB", bytes / 1048576.0);
    return fmt::format("{:.1f} KiB", bytes / 1024.0);
}

// Like `vdb_print -l`: per grid its index and name, type and class, active voxels, value
// range, bounds, voxel size, memory, and every metadata entry. `selector` (a name or an
// index, grid/grid_select.h) prints one grid only.
void printVdb(const fs::path& path, const std::string& selector) {
    const vdb::FileInfo file = vdb::describeVdbFile(path, selector);
    std::cout << "vdb " << path.string() << ": " << file.gridCount << " grid(s)\n";
    for (const vdb::GridInfo& g : file.grids) {
        std::cout << fmt::format(
            "  {} '{}' {} ({}): {} active voxels, {}, index bounds [{} {} {}]..[{} {} {}], voxel "
            "size ({:.4g} {:.4g} {:.4g}), world bounds ({:.4g} {:.4g} {:.4g})..({:.4g} {:.4g} "
            "{:.4g}), transform {}",
            g.index, g.name, g.type, g.gridClass, g.activeVoxels, g.valueRange, g.indexMin[0],
            g.indexMin[1], g.indexMin[2], g.indexMax[0], g.indexMax[1], g.indexMax[2],
            g.voxelSize[0], g.voxelSize[1], g.voxelSize[2], g.worldMin[0], g.worldMin[1],
            g.worldMin[2], g.worldMax[0], g.worldMax[1], g.worldMax[2], g.transform);
        // What `veil render` would upload: brick atlas or dense texture (src/fog).
        if (g.gridBytes > 0)
            std::cout << ", grid " << formatBytes(g.gridBytes) << ", GPU "
                      << formatBytes(g.gpuBytes);
        std::cout << "\n";
        for (const auto& m : g.metadata)
            std::cout << fmt::format("      {}: {} = {}\n", m.name, m.type, m.value);
    }
}

} // namespace

void addInfoCommand(CLI::App& app) {
    auto file = std::make_shared<std::string>();
    auto grid = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand("info", "Print what a scene (.json) or .vdb file holds");
    cmd->add_option("file", *file, "A scene file (.json) or an OpenVDB file (.vdb)")->required();
    cmd->add_option("--grid", *grid, ".vdb: only this grid (name or index)");
    auto json = std::make_shared<bool>(false);
    cmd->add_flag("--json", *json,
                  "A scene file: print it as plain JSON (comments removed) for json.load or jq");
    cmd->callback([file, grid, json] {
        const fs::path path(*file);
        // OpenVDB would block on a FIFO and read /dev/zero forever.
        std::error_code ec;
        const fs::file_status st = fs::status(path, ec);
        // A .vdb name that is no file but holds a frame pattern is a sequence.
        const bool sequence =
            !fs::exists(st) && lowerExtension(*file) == ".vdb" && scene::parseFilePattern(path);
        VEIL_CHECK(sequence || !fs::exists(st) || fs::is_regular_file(st),
                   "cannot read '{}': not a regular file", *file);
        if (*json) {
            VEIL_CHECK(lowerExtension(*file) != ".vdb",
                       "--json prints a scene file as plain JSON; '{}' is an OpenVDB file", *file);
            VEIL_CHECK(grid->empty(), "--grid is for .vdb files, not '{}'", *file);
            std::cout << scene::readSceneDocument(path).dump(2) << "\n";
        } else if (sequence) {
            // A sequence by its pattern: every file it finds.
            scene::FileSequence s;
            s.pattern = *scene::parseFilePattern(path);
            const std::vector<int> found = scene::existingFrames(s.pattern);
            VEIL_CHECK(!found.empty(), "no file matches the sequence '{}'", *file);
            s.spanFound(found);
            printSequence(s, grid->empty() ? "density" : *grid, "", !grid->empty());
        } else if (lowerExtension(*file) == ".vdb")
            printVdb(path, *grid);
        else {
            VEIL_CHECK(grid->empty(), "--grid is for .vdb files, not '{}'", *file);
            printScene(path);
        }
    });
}

} // namespace veil::app
