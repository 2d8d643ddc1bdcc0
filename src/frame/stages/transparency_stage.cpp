#include "frame/stages/transparency_stage.h"

#include "frame/stages/fog_stage.h"

#include "shaders/common/bindings.h"

#include <fmt/format.h>

// The OIT targets of the fog's compute emission (three at most) must fit the 8 image units
// that GL 4.5 guarantees (NVIDIA has exactly 8).
static_assert(VEIL_IMG_OIT_TARGET0 + 2 < 8, "OIT per-pixel emission images beyond unit 7");

namespace veil::frame {

std::unique_ptr<TransparencyStage>
TransparencyStage::create(const std::function<std::unique_ptr<oit::Technique>()>& make,
                          const scene::Scene& scene, gpu::ProgramManager& programs,
                          volume::FogPass* fog, const shadows::Technique::Receivers& receivers) {
    const std::size_t mark = programs.size();
    std::unique_ptr<oit::Technique> technique;
    try {
        technique = make();
    } catch (...) {
        for (gpu::ProgramHandle h : programs.handlesFrom(mark))
            programs.release(h);
        throw;
    }
    return create(std::move(technique), programs.handlesFrom(mark), scene, programs, fog,
                  receivers);
}

std::unique_ptr<TransparencyStage>
TransparencyStage::create(std::unique_ptr<oit::Technique> technique,
                          std::vector<gpu::ProgramHandle> techniquePrograms,
                          const scene::Scene& scene, gpu::ProgramManager& programs,
                          volume::FogPass* fog, const shadows::Technique::Receivers& receivers) {
    std::unique_ptr<TransparencyStage> stage(
        new TransparencyStage(std::move(technique), programs, fog));
    stage->owned_ = std::move(techniquePrograms);
    const std::size_t mark = programs.size();
    try {
        stage->build(scene, receivers);
    } catch (...) {
        for (gpu::ProgramHandle h : programs.handlesFrom(mark))
            programs.release(h);
        throw; // the stage releases the technique's
    }
    for (gpu::ProgramHandle h : programs.handlesFrom(mark))
        stage->owned_.push_back(h);
    return stage;
}

TransparencyStage::TransparencyStage(std::unique_ptr<oit::Technique> technique,
                                     gpu::ProgramManager& programs, volume::FogPass* fog)
    : programs_(programs), technique_(std::move(technique)), name_(technique_->name()), fog_(fog) {}

TransparencyStage::~TransparencyStage() {
    raster_.reset();
    technique_.reset();
    for (gpu::ProgramHandle h : owned_)
        programs_.release(h);
}

void TransparencyStage::build(const scene::Scene& scene,
                              const shadows::Technique::Receivers& receivers) {
    using gpu::ProgramDesc;
    const std::filesystem::path& visibility = receivers.visibility;
    const oit::Technique& t = *technique_;
    const bool piecewise = fog_ && t.fogSegments();
    if (piecewise) {
        const int last = t.geometryPasses() - 1;
        std::vector<std::string> defines = t.defines(last);
        defines.push_back(fmt::format("OIT_PASS {}", last));
        segments_ = fog_->addSegmentsProgram(programs_, std::move(defines), t.emitInclude());
    }
    const gpu::IncludeAliases emit{{"veil:oit_emit", t.emitInclude()}};
    for (int pass = 0; pass < t.geometryPasses(); ++pass) {
        std::vector<std::string> defines = t.defines(pass);
        defines.push_back(fmt::format("OIT_PASS {}", pass));
        std::vector<std::string> surfaceDefines = defines;
        if (fog_ && fog_->scatteredLightCache())
            surfaceDefines.push_back(kSurfaceScatteredLightDefine);
        surfaceDefines.insert(surfaceDefines.end(), receivers.defines.begin(),
                              receivers.defines.end());
        surface_.push_back(programs_.add(
            ProgramDesc::graphics("frame/mesh.vert", "frame/transparent.frag", surfaceDefines,
                                  {emit[0], {"veil:light_visibility", visibility}})));
        if (!fog_) continue;
        const oit::PerPixelEmit mode = piecewise ? oit::PerPixelEmit::None : t.perPixelEmit(pass);
        if (mode == oit::PerPixelEmit::Compute) {
            std::vector<std::string> computeDefines = defines;
            computeDefines.insert(computeDefines.begin(),
                                  "OIT_COMPUTE 1"); // before the technique's
            fogEmit_.push_back(programs_.add(
                ProgramDesc::compute("volume/fog_emit.comp", std::move(computeDefines), emit)));
        } else if (mode == oit::PerPixelEmit::Fragments) {
            fogEmit_.push_back(programs_.add(ProgramDesc::graphics(
                "volume/fullscreen.vert", "volume/fog_emit.frag", defines, emit)));
        } else {
            fogEmit_.emplace_back();
        }
    }
    if (scene.render.oitRasterizer == "compute") {
        std::vector<std::string> fineDefines = receivers.defines;
        if (fog_ && fog_->scatteredLightCache())
            fineDefines.push_back(kSurfaceScatteredLightDefine);
        raster_ = std::make_unique<ComputeRaster>(
            programs_, t,
            gpu::IncludeAliases{{"veil:raster_setup", "frame/raster_setup.glsl"},
                                {"veil:raster_surface", "frame/raster_surface.glsl"},
                                {"veil:raster_layout", "frame/raster_layout.glsl"},
                                {"veil:light_visibility", visibility}},
            fineDefines);
    }
}

std::vector<pass::Pass> TransparencyStage::passes(const pass::Assembly& assembly) {
    const bool piecewise = fog_ && technique_->fogSegments();
    if (fog_) fog_->setPiecewise(piecewise);
    oit::Technique::GeometryHooks hooks;
    if (assembly.has("ao.visibility")) hooks.reads.push_back("ao.visibility"); // [McGuire17 L. 2]
    if (fog_) hooks.reads.push_back("fog.radiance");
    hooks.surfaceProgram = [this](int pass) -> const gpu::Program& {
        return programs_.get(surface_[static_cast<std::size_t>(pass)]);
    };
    if (fog_ && !piecewise) // fog first: one contribution per pixel through the same oitEmit()
        hooks.beforeSurfaces = [this](const pass::Context& context, int pass) {
            emitFog(context, pass);
        };
    if (piecewise) // after every surface is stored: the fog between them, per segment
        hooks.afterSurfaces = [this](const pass::Context& context, int pass) {
            if (pass + 1 != technique_->geometryPasses()) return;
            fog_->marchSegments(
                context, programs_.get(segments_),
                [this, pass](const gpu::Program& p) { technique_->prepareProgram(pass, p); });
        };
    return raster_ ? raster_->passes(*technique_, std::move(hooks))
                   : technique_->passes(std::move(hooks));
}

void TransparencyStage::emitFog(const pass::Context& context, int pass) const {
    const oit::Technique& t = *technique_;
    const oit::PerPixelEmit mode = t.perPixelEmit(pass);
    if (mode == oit::PerPixelEmit::None) return;
    const gpu::Program& program = programs_.get(fogEmit_[static_cast<std::size_t>(pass)]);
    t.prepareProgram(pass, program);
    fog_->bindForEmit(program, context);
    program.use();
    if (mode == oit::PerPixelEmit::Compute) {
        const glm::ivec4 r = context.region;
        t.bindPerPixelEmit(pass, context);
        program.set("emitRegion", r); // a tile's pixels only
        glDispatchCompute((r.z - r.x + 7) / 8, (r.w - r.y + 7) / 8, 1);
        // The pass's blending, texel fetches and image loads see it.
        glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                        GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    } else {
        fog_->drawEmit();
    }
}

void TransparencyStage::addResources(pass::Resources& resources) const {
    for (const oit::Technique::Resource& r : technique_->resources())
        resources.add(r.name, r.texture);
}

std::size_t TransparencyStage::gpuBytes() const { return pixels_ * technique_->bytesPerPixel(); }

void TransparencyStage::resize(pass::Context& context) {
    technique_->resize(context);
    pixels_ = static_cast<std::size_t>(context.width) * static_cast<std::size_t>(context.height);
}

} // namespace veil::frame
