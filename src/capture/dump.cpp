#include "capture/dump.h"

#include "capture/resource_image.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "gpu/readback.h"
#include "io/exr_writer.h"
#include "io/provenance.h"
#include "io/vtk_export.h"

#include <fmt/format.h>

#include <algorithm>

#include <unistd.h>

namespace veil::capture {

namespace fs = std::filesystem;

// What the values mean, per resource (renderer.h lists them).
std::string resourceUnits(const std::string& resource) {
    if (resource == "hdr") return "linear HDR radiance, RGBA (A unused)";
    if (resource == "ldr") return "tone-mapped, sRGB-encoded display values in [0, 1]";
    if (resource == "depth")
        return "window depth in [0, 1] of the nearest opaque surface (nonlinear; 1 = nothing "
               "drawn); the render EXR's Z is it as view depth";
    if (resource == "shadow.depth")
        return "per light view (layer): linear depth along the view axis of the nearest opaque "
               "caster, normalized to the view's [near, far] (1 = none)";
    if (resource.rfind("shadow.", 0) == 0)
        return "the shadow technique's maps, one layer per light view (docs/shadows.md)";
    if (resource == "fog.radiance")
        return "RGB radiance in-scattered by the fog toward the camera, A = mean fog depth "
               "(view units); at 1/render.fog_resolution of the frame size";
    if (resource == "fog.light_transmittance")
        return "transmittance toward the primary light, one value per texel of the first "
               "volume's light-space grid (spacing and origin in texels)";
    return "raw texel values";
}

namespace {

std::string unitsOf(const std::string& resource) { return resourceUnits(resource); }

// A single-channel texture (depth or red) as floats, row 0 = top for 2D.
std::vector<float> readRed(const gpu::Texture& t, GLenum format) {
    std::vector<float> v(std::size_t(t.width()) * t.height() * std::max(1, t.depth()));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(t.id(), 0, format, GL_FLOAT, static_cast<GLsizei>(v.size() * sizeof(float)),
                      v.data());
    if (t.target() == GL_TEXTURE_2D) {
        const std::size_t row = std::size_t(t.width());
        for (int y = 0; y < t.height() / 2; ++y)
            std::swap_ranges(v.begin() + y * row, v.begin() + (y + 1) * row,
                             v.begin() + (t.height() - 1 - y) * row);
    }
    return v;
}

// Characters safe in a file name: the resource names are ids like "shadow.0", kept as they are.
std::string fileStem(const std::string& resource) {
    std::string s = resource;
    for (char& c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-'))
            c = '_';
    return s;
}

} // namespace

void checkDumpDirectory(const fs::path& given) {
    // "out/dump/" names the folder "out/dump": its parent is "out", not "out/dump".
    const fs::path dir = given.has_filename() ? given : given.parent_path();
    std::error_code ec;
    const fs::file_status st = fs::status(dir, ec);
    VEIL_CHECK(!fs::exists(st) || fs::is_directory(st), "--dump '{}': exists and is not a folder",
               dir.string());
    VEIL_CHECK(fs::exists(st) ||
                   fs::is_directory(dir.parent_path().empty() ? "." : dir.parent_path()),
               "--dump '{}': its parent folder does not exist", dir.string());
    VEIL_CHECK(!fs::is_directory(st) || fs::is_empty(dir, ec) ||
                   fs::is_regular_file(dir / "manifest.json", ec),
               "--dump '{}': the folder holds files but no manifest.json (not an earlier "
               "dump, which a dump replaces as a whole): give an empty or new folder",
               dir.string());
}

io::ExrImage resourceExr(const ResourceImage& image,
                         std::vector<std::pair<std::string, std::string>> strings) {
    io::ExrImage exr;
    exr.width = image.width;
    exr.height = image.height;
    exr.channels = image.channels;
    exr.pixels = image.pixels;
    exr.strings = std::move(strings);
    return exr;
}

namespace {

// The folder a dump is written into before it is renamed to `target` (a sibling, so the
// rename stays on one file system).
fs::path stagingFolderFor(const fs::path& target, const char* kind) {
    const fs::path abs = fs::absolute(target).lexically_normal();
    const fs::path clean = abs.has_filename() ? abs : abs.parent_path();
    return clean.parent_path() /
           fmt::format(".{}.{}-{}", clean.filename().string(), kind, static_cast<long>(getpid()));
}

nlohmann::json writeDump(const frame::Renderer& renderer, const fs::path& dir);

} // namespace

nlohmann::json dumpFrame(const frame::Renderer& renderer, const fs::path& target) {
    checkDumpDirectory(target);
    const fs::path staging = stagingFolderFor(target, "dump");
    const fs::path old = stagingFolderFor(target, "old");
    std::error_code ec;
    fs::remove_all(staging, ec);
    fs::create_directory(staging, ec);
    VEIL_CHECK(!ec, "--dump '{}': cannot create the folder '{}' ({})", target.string(),
               staging.string(), ec.message());
    try {
        nlohmann::json manifest = writeDump(renderer, staging);
        const fs::path dest = fs::absolute(target).lexically_normal();
        const fs::path place = dest.has_filename() ? dest : dest.parent_path();
        if (fs::exists(place)) { // an earlier dump (checkDumpDirectory), replaced
            fs::rename(place, old);
            fs::rename(staging, place, ec);
            if (ec) {
                std::error_code back;
                fs::rename(old, place, back);
                throw fs::filesystem_error("rename", staging, place, ec);
            }
            fs::remove_all(old, ec);
        } else {
            fs::rename(staging, place);
        }
        return manifest;
    } catch (const fs::filesystem_error& e) {
        fs::remove_all(staging, ec);
        throw Error(fmt::format("--dump '{}': cannot move the dump into place: {}", target.string(),
                                e.code().message()));
    } catch (...) {
        fs::remove_all(staging, ec);
        throw;
    }
}

namespace {

nlohmann::json writeDump(const frame::Renderer& renderer, const fs::path& dir) {
    nlohmann::json entries = nlohmann::json::array();
    for (const std::string& name : renderer.passes().resources()) {
        nlohmann::json e = {{"resource", name}};
        const gpu::Texture* t = renderer.resourceTexture(name);
        if (!t || !*t) {
            e["dumpable"] = false;
            e["reason"] = name.rfind("oit.", 0) == 0
                              ? fmt::format("lives inside the OIT technique '{}' (no frame "
                                            "texture)",
                                            renderer.oitName())
                              : std::string("no texture behind this resource");
            entries.push_back(e);
            continue;
        }
        const GLenum f = t->format();
        e["format"] = formatName(f);
        e["units"] = unitsOf(name);
        e["width"] = t->width();
        e["height"] = t->height();
        if (t->target() == GL_TEXTURE_3D && !io::vtiSupported()) {
            e["dumpable"] = false;
            e["reason"] = "3D texture: .vti needs VTK, which this veil was built without "
                          "(scripts/install-deps.sh --test, or sudo apt install libvtk9-dev, "
                          "then rebuild)";
        } else if (t->target() == GL_TEXTURE_3D) {
            io::DenseGrid g;
            g.name = name;
            g.dims = {t->width(), t->height(), t->depth()};
            g.values = readRed(*t, GL_RED);
            // Self-describing in ParaView as the EXR dumps are through their header.
            g.fieldData = {{"veil_resource", name},
                           {"veil_format", formatName(f)},
                           {"veil_units", unitsOf(name)},
                           {"veil_oit", renderer.oitName()}};
            const std::string file = fileStem(name) + ".vti";
            io::writeVti(dir / file, g);
            e["depth"] = t->depth();
            e["file"] = file;
            e["type"] = "float32 VTK ImageData (vtkXMLImageDataWriter), one scalar per texel";
            e["dumpable"] = true;
        } else if (t->target() == GL_TEXTURE_2D) {
            const io::ExrImage exr =
                resourceExr(readResourceImage(*t), {{"veil:resource", name},
                                                    {"veil:format", formatName(f)},
                                                    {"veil:units", unitsOf(name)}});
            const std::string file = fileStem(name) + ".exr";
            io::writeExr(dir / file, exr);
            e["file"] = file;
            e["channels"] = exr.channels;
            e["type"] = "float32 OpenEXR";
            e["dumpable"] = true;
        } else if (t->target() == GL_TEXTURE_2D_ARRAY && f != GL_R32UI && f != GL_RGBA32UI) {
            // One EXR per layer (a shadow technique's maps: one layer per light view).
            const int layers = resourceLayers(*t);
            nlohmann::json files = nlohmann::json::array();
            for (int k = 0; k < layers; ++k) {
                const std::string file = fmt::format("{}.layer{}.exr", fileStem(name), k);
                io::writeExr(dir / file, resourceExr(readResourceImage(*t, k),
                                                     {{"veil:resource", name},
                                                      {"veil:layer", std::to_string(k)},
                                                      {"veil:format", formatName(f)},
                                                      {"veil:units", unitsOf(name)}}));
                files.push_back(file);
            }
            e["layers"] = layers;
            e["files"] = files;
            e["type"] = "float32 OpenEXR, one file per layer (light view)";
            e["dumpable"] = true;
        } else {
            e["dumpable"] = false;
            e["reason"] = fmt::format(
                "texture target 0x{:04x} (e.g. multisample, integer lists) cannot be read "
                "back",
                t->target());
        }
        entries.push_back(e);
    }
    nlohmann::json manifest = {{"renderer", "veil " + io::veilVersion()},
                               {"veil_commit", io::gitCommit()},
                               {"oit", renderer.oitName()},
                               {"camera", renderer.camera().name},
                               {"frame_width", renderer.width()},
                               {"frame_height", renderer.height()},
                               {"passes", renderer.passes().describe()},
                               {"resources", entries}};
    writeTextFileAtomically(dir / "manifest.json", manifest.dump(2) + "\n");
    return manifest;
}

} // namespace

} // namespace veil::capture
