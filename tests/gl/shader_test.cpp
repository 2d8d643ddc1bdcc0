// Shader loading: #include expansion, #line markers that make compile errors name the real
// file and line, and hot reload through stable program handles.
#include "gl_fixture.h"

#include "base/error.h"
#include "frame/stages/compute_raster.h"
#include "gpu/shader.h"
#include "oit/phenomenological/phenomenological.h"
#include "oit/reference/reference.h"
#include "oit/technique.h"
#include "shadows/technique.h"
#include "support/test_support.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <memory>
#include <set>

namespace veil::test {

namespace fs = std::filesystem;

namespace {
fs::path writeShader(const std::string& name, const std::string& text) {
    const fs::path dir = outputDir() / "shader_test";
    fs::create_directories(dir);
    const fs::path p = dir / name;
    std::ofstream(p) << text;
    return p;
}

const char* kVertex = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
} // namespace

class ShaderTest : public GlTest {};

TEST_F(ShaderTest, IncludeIsExpandedOnceWithLineMarkers) {
    writeShader("common.glsl", "float helper() { return 1.0; }\n");
    const fs::path main = writeShader("inc_main.frag", "#version 450 core\n"
                                                       "#include \"common.glsl\"\n"
                                                       "#include \"common.glsl\"\n"
                                                       "out vec4 c;\n"
                                                       "void main() { c = vec4(helper()); }\n");
    gpu::ShaderSource src = gpu::preprocessShader(main, {"FOO 2"}, main.parent_path());
    ASSERT_EQ(src.files.size(), 2u);
    EXPECT_NE(src.files[1].find("common.glsl"), std::string::npos);
    EXPECT_NE(src.text.find("#define FOO 2"), std::string::npos);
    EXPECT_NE(src.text.find("#line 1 1"), std::string::npos);
    // After the include, numbering resumes at line 3 of file 0.
    EXPECT_NE(src.text.find("#line 3 0"), std::string::npos);
    // The helper is defined once although included twice.
    const auto first = src.text.find("float helper()");
    EXPECT_EQ(src.text.find("float helper()", first + 1), std::string::npos);
    gpu::ProgramDesc desc;
    desc.stages = {{GL_VERTEX_SHADER, writeShader("inc.vert", kVertex)},
                   {GL_FRAGMENT_SHADER, main}};
    EXPECT_NO_THROW(gpu::Program p(desc));
}

TEST_F(ShaderTest, CompileErrorNamesIncludedFileAndLine) {
    writeShader("broken.glsl", "float ok() { return 1.0; }\n"
                               "float bad() { return undefinedThing; }\n");
    const fs::path main = writeShader("err_main.frag", "#version 450 core\n"
                                                       "#include \"broken.glsl\"\n"
                                                       "out vec4 c;\n"
                                                       "void main() { c = vec4(bad()); }\n");
    gpu::ProgramDesc desc;
    desc.stages = {{GL_VERTEX_SHADER, writeShader("err.vert", kVertex)},
                   {GL_FRAGMENT_SHADER, main}};
    try {
        gpu::Program p(desc);
        FAIL() << "expected a compile error";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("broken.glsl:2"), std::string::npos) << msg;
    }
}

TEST_F(ShaderTest, TranslatesMesaAndNvidiaLogFormats) {
    const std::vector<std::string> files = {"a.frag", "b.glsl"};
    EXPECT_EQ(gpu::translateShaderLog("1:7(12): error: x\n", files), "b.glsl:7:12: error: x\n");
    EXPECT_EQ(gpu::translateShaderLog("0(3) : error C1008: y\n", files),
              "a.frag:3 : error C1008: y\n");
    EXPECT_EQ(gpu::translateShaderLog("plain line\n", files), "plain line\n");
}

TEST_F(ShaderTest, MissingIncludeAndCycleAreErrors) {
    const fs::path missing =
        writeShader("missing.frag", "#version 450 core\n#include \"nope.glsl\"\n");
    EXPECT_THROW(gpu::preprocessShader(missing, {}, missing.parent_path()), Error);
    writeShader("cycle_a.glsl", "#include \"cycle_b.glsl\"\n");
    writeShader("cycle_b.glsl", "#include \"cycle_a.glsl\"\n");
    const fs::path cyc =
        writeShader("cycle.frag", "#version 450 core\n#include \"cycle_a.glsl\"\n");
    try {
        gpu::preprocessShader(cyc, {}, cyc.parent_path());
        FAIL() << "expected an include-cycle error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cycle"), std::string::npos) << e.what();
    }
    const fs::path noVersion = writeShader("noversion.frag", "void main() {}\n");
    EXPECT_THROW(gpu::preprocessShader(noVersion, {}, noVersion.parent_path()), Error);
}

TEST_F(ShaderTest, ReloadSwapsProgramBehindStableHandle) {
    const fs::path frag = writeShader("reload.frag", "#version 450 core\nout vec4 c;\n"
                                                     "void main() { c = vec4(1.0); }\n");
    gpu::ProgramManager manager;
    gpu::ProgramHandle h =
        manager.add(gpu::ProgramDesc::graphics(writeShader("reload.vert", kVertex), frag));
    const GLuint before = manager.get(h).id();
    EXPECT_EQ(manager.reloadAll(), 0);
    const GLuint after = manager.get(h).id();
    EXPECT_NE(after, 0u);
    EXPECT_FALSE(glIsProgram(before)) << "the old program must be deleted on reload";
    // A broken edit keeps the last good program.
    writeShader("reload.frag", "#version 450 core\nvoid main() { syntax error }\n");
    EXPECT_EQ(manager.reloadAll(), 1);
    EXPECT_EQ(manager.get(h).id(), after);
    EXPECT_TRUE(glIsProgram(after));
}

namespace {

// Every program the project builds, as src/ builds it:
//  - frame (src/frame/stages): mesh.vert with opaque.frag and shadow.frag, tonemap.comp,
//    and per OIT technique and geometry pass transparent.frag and the fog's fog_emit.frag or
//    fog_emit.comp (by perPixelEmit(pass)) with the technique's defines(pass) + "OIT_PASS
//    <pass>" and "veil:oit_emit" -> emitInclude();
//  - the OIT techniques' own programs (src/oit/<technique>/*.cpp), which Registry::create
//    also compiles;
//  - fog (src/fog/fog_pass.cpp), voxelizer (src/voxelize/gpu_voxelizer.cpp: every
//    CONSERVATIVE / THREE_AXIS / SOLID / LOCAL / DEPTH_PASS combination its methods use) and
//    the slice-map query probe (tests/gl/voxelize_solid_local_test.cpp).
// Techniques this driver lacks (moment *-16: fragment shader interlock) are listed in
// `skipped`; so are NV_CONSERVATIVE variants without GL_NV_conservative_raster.
struct ProjectPrograms {
    std::vector<gpu::ProgramDesc> programs;
    std::vector<std::string> skipped;
};

ProjectPrograms projectPrograms(const gpu::ContextInfo& info, gpu::ProgramManager& manager) {
    using gpu::ProgramDesc;
    ProjectPrograms out;
    auto& P = out.programs;
    // Shadows: every registered technique (its constructor adds its own programs to the
    // manager: collected at the end), and each receiver with its visibility include.
    std::vector<gpu::IncludeAliases> visibilities;
    for (const shadows::TechniqueInfo& t : shadows::Registry::instance().all()) {
        if (t.isAvailable && !t.isAvailable(info)) {
            out.skipped.push_back("shadows " + t.name + " (not available on this driver)");
            continue;
        }
        try {
            auto technique = shadows::Registry::instance().create(t.name, info, manager);
            visibilities.push_back({{"veil:light_visibility", technique->visibilityInclude()}});
        } catch (const Error& e) {
            ADD_FAILURE() << "shadows " << t.name << ": " << e.what();
        }
    }
    // The shadow technique template (src/shadows/_template), not registered by default.
    visibilities.push_back({{"veil:light_visibility", "shadows/_template/visibility.glsl"}});
    for (const auto& v : visibilities) {
        P.push_back(ProgramDesc::graphics("frame/mesh.vert", "frame/opaque.frag", {}, v));
        P.push_back(
            ProgramDesc::graphics("frame/mesh.vert", "frame/opaque.frag", {"VEIL_AO 1"}, v));
        // receiver_slope geometric, none and plane-bias (shadows::opaqueMapDefines;
        // derivatives is the default above).
        for (const char* slope :
             {"VEIL_RECEIVER_SLOPE 1", "VEIL_RECEIVER_SLOPE 2", "VEIL_RECEIVER_SLOPE 3"})
            P.push_back(ProgramDesc::graphics("frame/mesh.vert", "frame/opaque.frag", {slope}, v));
        P.push_back(ProgramDesc::compute("volume/fog_march.comp", {}, v));
        P.push_back(ProgramDesc::graphics("frame/mesh.vert", "frame/transparent.frag",
                                          {"OIT_PASS 0"},
                                          {{"veil:oit_emit", "oit/blend/emit.glsl"}, v[0]}));
    }
    const gpu::IncludeAliases visibility = visibilities.at(0); // `opaque`, registered first
    P.push_back(ProgramDesc::compute("frame/tonemap.comp"));
    // The stage template (src/frame/stages/_template), inserted by its test only.
    P.push_back(ProgramDesc::compute("frame/_template/template.comp"));
    for (const char* ao : {"frame/ao/csz.comp", "frame/ao/csz_downsample.comp", "frame/ao/sao.comp",
                           "frame/ao/blur.comp"})
        P.push_back(ProgramDesc::compute(ao)); // the frame's AO pass (render.ao)
    P.push_back(ProgramDesc::compute("volume/light_transmittance.comp"));
    // The scattered-light cache's GPU bake (src/fog/scattered_light_bake.cpp), with and without
    // the emission channel.
    P.push_back(ProgramDesc::compute("volume/cache_bake.comp", {"VEIL_VOLUME_SLOTS 1"}));
    P.push_back(ProgramDesc::compute("volume/cache_bake.comp",
                                     {"VEIL_VOLUME_SLOTS 2", "VEIL_VOLUME_EMISSION 1"}));

    // OIT: one technique object per registered name (and the phenomenological options that
    // add passes), the frame's programs built from what the object says.
    oit::PhenomenologicalParams volumeLowRes;
    volumeLowRes.volumeRefraction = true;
    volumeLowRes.particleDownsample = 2;
    std::vector<std::pair<std::string, nlohmann::json>> techniques;
    for (const oit::TechniqueInfo& t : oit::Registry::instance().all()) {
        techniques.emplace_back(t.name, nlohmann::json());
        if (t.name == "phenomenological")
            techniques.emplace_back(t.name, oit::toProperties(volumeLowRes));
    }
    for (const auto& [name, props] : techniques) {
        const oit::TechniqueInfo& t = oit::Registry::instance().get(name);
        if (t.isAvailable && !t.isAvailable(info)) {
            out.skipped.push_back(name + " (not available on this driver)");
            continue;
        }
        std::unique_ptr<oit::Technique> technique;
        try {
            technique = oit::Registry::instance().create(name, info, manager, props);
        } catch (const Error& e) {
            ADD_FAILURE() << name << ": " << e.what();
            continue;
        }
        for (int pass = 0; pass < technique->geometryPasses(); ++pass) {
            std::vector<std::string> defines = technique->defines(pass);
            defines.push_back(fmt::format("OIT_PASS {}", pass));
            const gpu::IncludeAliases emit{{"veil:oit_emit", technique->emitInclude()}};
            P.push_back(ProgramDesc::graphics("frame/mesh.vert", "frame/transparent.frag", defines,
                                              {emit[0], visibility[0]}));
            // The fog's per-pixel emission as the frame builds it (oit::PerPixelEmit).
            const oit::PerPixelEmit mode = technique->perPixelEmit(pass);
            if (mode == oit::PerPixelEmit::Compute) {
                std::vector<std::string> compute = defines;
                compute.insert(compute.begin(), "OIT_COMPUTE 1");
                P.push_back(ProgramDesc::compute("volume/fog_emit.comp", compute, emit));
            } else if (mode == oit::PerPixelEmit::Fragments) {
                P.push_back(ProgramDesc::graphics("volume/fullscreen.vert", "volume/fog_emit.frag",
                                                  defines, emit));
            }
            // The piecewise fog marcher (src/fog/fog_pass.cpp), with every shadow technique.
            if (technique->fogSegments() && pass + 1 == technique->geometryPasses())
                for (const auto& v : visibilities)
                    P.push_back(
                        ProgramDesc::compute("volume/fog_segments.comp", defines, {v[0], emit[0]}));
        }
        // The compute rasterizer's stages with the technique's emit file (its constructor adds
        // them to the manager), as frame::Renderer builds them.
        if (t.computeRaster)
            frame::ComputeRaster(manager, *technique,
                                 {{"veil:raster_setup", "frame/raster_setup.glsl"},
                                  {"veil:raster_surface", "frame/raster_surface.glsl"},
                                  {"veil:raster_layout", "frame/raster_layout.glsl"},
                                  visibility[0]});
    }
    // The technique template (src/oit/_template), not registered by default.
    {
        const gpu::IncludeAliases emit{{"veil:oit_emit", "oit/_template/emit.glsl"}};
        P.push_back(ProgramDesc::graphics("frame/mesh.vert", "frame/transparent.frag",
                                          {"OIT_PASS 0"}, {emit[0], visibility[0]}));
    }
    // The techniques' own programs (their constructors above compiled them too).
    for (const char* comp :
         {"oit/wboit/resolve.comp", "oit/moment/resolve.comp", "oit/stochastic/fold.comp",
          "oit/stochastic/resolve.comp", "oit/phenomenological/resolve.comp",
          "oit/phenomenological/thickness.comp", "oit/phenomenological/downsample_depth.comp",
          "oit/phenomenological/upsample.comp"})
        P.push_back(ProgramDesc::compute(comp));
    P.push_back(
        ProgramDesc::compute("oit/reference/resolve.comp",
                             {fmt::format("OIT_REF_MAX_FRAGMENTS {}",
                                          oit::ReferenceTechnique::kDefaultMaxFragmentsPerPixel)}));
    P.push_back(
        ProgramDesc::graphics("oit/stochastic/copy_depth.vert", "oit/stochastic/copy_depth.frag"));

    // Voxelizer: raster (plain), conservative, three-axis, each with the range pass, solid
    // and local slicing where the method allows them.
    for (int kind = 0; kind < 3; ++kind) {              // 0 raster, 1 conservative, 2 three-axis
        for (int variant = 0; variant < 4; ++variant) { // plain, DEPTH_PASS, SOLID, LOCAL
            if (kind == 2 && variant != 0) continue;    // three-axis: surface, uniform slicing
            std::vector<std::string> d;
            if (kind >= 1) d.push_back("CONSERVATIVE");
            if (kind == 2) d.push_back("THREE_AXIS");
            if (variant == 1) d.push_back("DEPTH_PASS");
            if (variant == 2) d.push_back("SOLID");
            if (variant == 3) d.push_back("LOCAL");
            ProgramDesc desc;
            desc.stages.push_back({GL_VERTEX_SHADER, "voxelize/voxelize.vert"});
            if (kind >= 1)
                desc.stages.push_back({GL_GEOMETRY_SHADER, "voxelize/conservative.geom"});
            desc.stages.push_back({GL_FRAGMENT_SHADER, "voxelize/voxelize.frag"});
            desc.defines = d;
            P.push_back(desc);
            if (kind >= 1) {
                if (info.conservativeRaster) {
                    desc.defines.push_back("NV_CONSERVATIVE");
                    P.push_back(desc);
                } else if (kind == 1 && variant == 0) {
                    out.skipped.push_back(
                        "NV_CONSERVATIVE variants (no GL_NV_conservative_raster)");
                }
            }
        }
    }
    P.push_back(ProgramDesc::compute("voxelize/pack.comp"));
    P.push_back(ProgramDesc::compute("voxelize/merge_axes.comp"));
    P.push_back(ProgramDesc::compute("voxelize/compute.comp"));
    P.push_back(ProgramDesc::compute("voxelize/compute.comp", {"COUNT_TILES"}));
    P.push_back(ProgramDesc::compute("voxelize/query_probe.comp"));
    // transmittance-slicemap: the variants its defaults do not build, and the test probe.
    for (const char* d : {"LOCAL", "CONSERVATIVE"})
        P.push_back(ProgramDesc::graphics("frame/mesh.vert",
                                          "shadows/transmittance_slicemap/caster.frag", {d}));
    P.push_back(ProgramDesc::compute("shadows/transmittance_slicemap/count_probe.comp"));
    // What the techniques' constructors added (shadow techniques' own passes).
    for (const gpu::ProgramDesc& d : manager.descriptions())
        P.push_back(d);
    return out;
}

} // namespace

TEST_F(ShaderTest, ProjectShadersCompile) {
    // Every program the project builds compiles and links on this driver, and every file under
    // shaders/ is part of at least one of them (a shader nobody compiles fails here).
    gpu::ProgramManager manager;
    const ProjectPrograms all = projectPrograms(info(), manager);
    std::set<fs::path> used;
    for (const gpu::ProgramDesc& desc : all.programs) {
        EXPECT_NO_THROW(gpu::Program{desc}) << desc.label();
        for (const gpu::ShaderStage& stage : desc.stages)
            for (const std::string& f : gpu::preprocessShader(stage.file, desc.defines,
                                                              gpu::shaderDirectory(), desc.aliases)
                                            .files)
                used.insert(fs::weakly_canonical(gpu::shaderDirectory() / f));
    }
    std::printf("%zu programs compiled; skipped:", all.programs.size());
    for (const std::string& s : all.skipped)
        std::printf(" %s;", s.c_str());
    std::printf("\n");
    EXPECT_GE(all.programs.size(), 40u);
    int files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(gpu::shaderDirectory())) {
        if (!entry.is_regular_file()) continue;
        ++files;
        EXPECT_TRUE(used.count(fs::weakly_canonical(entry.path())))
            << fs::relative(entry.path(), gpu::shaderDirectory())
            << " is in no compiled program: add the program that uses it to projectPrograms()";
    }
    EXPECT_GT(files, 40);
}

} // namespace veil::test
