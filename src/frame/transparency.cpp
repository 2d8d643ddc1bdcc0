#include "frame/transparency.h"

#include "shaders/common/bindings.h"

#include <fmt/format.h>

// The OIT targets of the fog's compute emission (three at most) must fit the 8 image units
// that GL 4.5 guarantees (NVIDIA has exactly 8).
static_assert(VEIL_IMG_OIT_TARGET0 + 2 < 8, "OIT per-pixel emission images beyond unit 7");

namespace veil::frame {

namespace {
// The fog between the technique's sorted surfaces, piecewise, for a technique with
// fogSegments() (`reference`); off for the others.
void configureFogSegments(const oit::Technique& technique, volume::FogPass* fog) {
    if (!fog) return;
    if (!technique.fogSegments()) {
        fog->disableSegments();
        return;
    }
    const int last = technique.geometryPasses() - 1;
    std::vector<std::string> defines = technique.defines(last);
    defines.push_back(fmt::format("OIT_PASS {}", last));
    fog->enableSegments(std::move(defines), technique.emitInclude());
}
} // namespace

TransparencyPrograms buildTransparencyPrograms(const oit::Technique& technique,
                                               volume::FogPass* fog, gpu::ProgramManager& programs,
                                               const gpu::IncludeAliases& visibility) {
    using gpu::ProgramDesc;
    configureFogSegments(technique, fog);
    TransparencyPrograms built;
    for (int pass = 0; pass < technique.geometryPasses(); ++pass) {
        std::vector<std::string> defines = technique.defines(pass);
        defines.push_back(fmt::format("OIT_PASS {}", pass));
        built.surface.push_back(programs.add(
            ProgramDesc::graphics("frame/mesh.vert", "frame/transparent.frag", defines,
                                  {{"veil:oit_emit", technique.emitInclude()}, visibility[0]})));
        if (!fog) continue;
        const oit::PerPixelEmit mode =
            fog->segmented() ? oit::PerPixelEmit::None : technique.perPixelEmit(pass);
        const gpu::IncludeAliases emit{{"veil:oit_emit", technique.emitInclude()}};
        if (mode == oit::PerPixelEmit::Compute) {
            std::vector<std::string> computeDefines = defines;
            computeDefines.insert(computeDefines.begin(),
                                  "OIT_COMPUTE 1"); // before the technique's
            built.fogEmit.push_back(programs.add(
                ProgramDesc::compute("volume/fog_emit.comp", std::move(computeDefines), emit)));
        } else if (mode == oit::PerPixelEmit::Fragments) {
            built.fogEmit.push_back(programs.add(ProgramDesc::graphics(
                "volume/fullscreen.vert", "volume/fog_emit.frag", defines, emit)));
        } else {
            built.fogEmit.emplace_back();
        }
    }
    return built;
}

oit::Technique::GeometryHooks transparencyHooks(const oit::Technique& technique,
                                                volume::FogPass* fog,
                                                const gpu::ProgramManager& programs,
                                                const TransparencyPrograms& built,
                                                std::vector<std::string> reads) {
    oit::Technique::GeometryHooks hooks;
    hooks.reads = std::move(reads);
    hooks.surfaceProgram = [&programs, surface = built.surface](int pass) -> const gpu::Program& {
        return programs.get(surface[static_cast<std::size_t>(pass)]);
    };
    if (!fog) return hooks;
    const oit::Technique* t = &technique;
    // Fog first: one contribution per pixel through the same oitEmit().
    hooks.beforeSurfaces = [t, fog, &programs, emit = built.fogEmit](const pass::Context& context,
                                                                     int pass) {
        const oit::PerPixelEmit mode =
            fog->segmented() ? oit::PerPixelEmit::None : t->perPixelEmit(pass);
        if (mode == oit::PerPixelEmit::None) return;
        const gpu::Program& program = programs.get(emit[static_cast<std::size_t>(pass)]);
        t->prepareProgram(pass, program);
        fog->bindForEmit(program, context);
        program.use();
        if (mode == oit::PerPixelEmit::Compute) {
            const glm::ivec4 r = context.region;
            t->bindPerPixelEmit(pass, context);
            program.set("emitRegion", r); // a tile's pixels only
            glDispatchCompute((r.z - r.x + 7) / 8, (r.w - r.y + 7) / 8, 1);
            // The pass's blending, texel fetches and image loads see it.
            glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                            GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        } else {
            fog->drawEmit();
        }
    };
    // After every surface is stored: the fog between them, per segment.
    hooks.afterSurfaces = [t, fog](const pass::Context& context, int pass) {
        if (!fog->segmented() || pass + 1 != t->geometryPasses()) return;
        fog->marchSegments(context,
                           [t, pass](const gpu::Program& p) { t->prepareProgram(pass, p); });
    };
    return hooks;
}

} // namespace veil::frame
