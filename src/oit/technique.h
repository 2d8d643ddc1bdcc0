// The transparency interface (docs/architecture.md): a technique owns its accumulation targets,
// blend state and resolve, and provides the GLSL file defining
//     void oitEmit(OitFragment f);   (shaders/oit/fragment.glsl)
// which surface shaders call per fragment, and the fog once per pixel with what the marcher
// accumulated: from a compute shader (volume/fog_emit.comp) where the technique writes its
// targets through OIT_TARGET / OIT_WRITE (perPixelEmit() == Compute), otherwise as a
// full-screen fragment (volume/fog_emit.frag). `radiance` is premultiplied by coverage
// alpha; the background behind the contribution is modulated by
// (1 - alpha + alpha * transmission) [McGuire16 Eq. 2].
#pragma once

#include "base/named_registry.h"
#include "base/properties.h"
#include "gpu/context.h"
#include "gpu/objects.h"
#include "gpu/pipeline_state.h"
#include "gpu/shader.h"
#include "pass/pass.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace veil::oit {

// What the frame gives a technique is the pass::Context of every pass (src/pass/pass.h):
// hdrColor holds the opaque image and receives the composite; depth is the opaque depth
// (techniques test against it, never write it); the state tracker (a technique applies a
// declared PipelineState before each of its draws and clears and issues no raw GL state calls);
// ambientOcclusion (render.ao on: techniques that infer AO at partial coverage read it);
// region: the pixels of the per-pixel passes (the viewer's tiled refinement sets one tile and
// its margin, frame/renderer.h). Every compute pass of a technique (its resolve and any pass
// feeding it) dispatches over the region only, the region's origin an offset uniform in the
// shader (shaders/common/region.glsl), and leaves hdrColor outside it untouched. The
// accumulation targets outside it hold whatever they held (the draws and clears are scissored
// to it): a technique whose result at a pixel reads accumulation or hdrColor at other pixels
// says how far (Technique::refineMarginPx()). opaqueColor: during a refinement the opaque image
// of the whole frame, for techniques that read the background at other pixels than their own
// (phenomenological's refraction and diffusion).

// targets.region clamped to the frame, the whole frame when it is empty.
inline glm::ivec4 frameRegion(const pass::Context& targets) {
    const glm::ivec4 r = targets.region;
    const glm::ivec4 c(std::max(r.x, 0), std::max(r.y, 0), std::min(r.z, targets.width),
                       std::min(r.w, targets.height));
    if (c.z <= c.x || c.w <= c.y) return {0, 0, targets.width, targets.height};
    return c;
}

// The texels of a grid `scale` times coarser than the frame (texel q covers pixels
// q * scale .. q * scale + scale - 1) that cover region `r`, grown by `pad` texels on each side
// and clamped to the coarse grid of `size` texels.
inline glm::ivec4 coarseRegion(glm::ivec4 r, int scale, int pad, glm::ivec2 size) {
    return {std::max(r.x / scale - pad, 0), std::max(r.y / scale - pad, 0),
            std::min((r.z + scale - 1) / scale + pad, size.x),
            std::min((r.w + scale - 1) / scale + pad, size.y)};
}

// Dispatches `program` (8 x 8 invocations per group, current) over region `r` (x0 y0 x1 y1),
// setting its `region` uniform (shaders/common/region.glsl).
inline void dispatchRegion(const gpu::Program& program, glm::ivec4 r) {
    program.set("region", r);
    glDispatchCompute(static_cast<GLuint>((r.z - r.x + 7) / 8),
                      static_cast<GLuint>((r.w - r.y + 7) / 8), 1);
}

// What every accumulation pass starts from: the full viewport, depth tested against the
// opaque depth and not written, no culling, no blending.
inline gpu::PipelineState accumulationState(const pass::Context& targets) {
    gpu::PipelineState s;
    s.view(targets.width, targets.height).depth(GL_LESS, false);
    return s;
}

// How geometry pass `pass` takes per-pixel contributions (the fog's, one per pixel):
//   Fragments  a full-screen draw through the pass's blend state (fog_emit.frag);
//   Compute    a compute shader including the emit file with OIT_COMPUTE defined, one
//              invocation per pixel writing the targets as images (fog_emit.comp), dispatched
//              after beginAccumulate() and bindPerPixelEmit(), before the pass's draws;
//   None       the pass takes none (its oitEmit() would drop them).
enum class PerPixelEmit { Fragments, Compute, None };

class Technique {
public:
    virtual ~Technique() = default;
    virtual std::string name() const = 0;
    // GLSL file (relative to shaders/) defining oitEmit(); included as "veil:oit_emit".
    virtual std::filesystem::path emitInclude() const = 0;
    // Defines for the transparent-surface program of geometry pass `pass`; the frame adds
    // "OIT_PASS <pass>" itself.
    virtual std::vector<std::string> defines(int pass) const {
        (void)pass;
        return {};
    }
    // Number of passes over the transparent geometry per frame (moment-based OIT: 2,
    // stochastic with repeated seeds: several). Each pass gets its own program.
    virtual int geometryPasses() const { return 1; }
    // Called when the frame targets are (re)created.
    virtual void resize(const pass::Context& targets) = 0;
    // Binds the accumulation targets and blend state for geometry pass `pass`, and sets any
    // uniforms it needs on `program` (the pass's transparent-surface program).
    virtual void beginAccumulate(int pass, const pass::Context& targets,
                                 const gpu::Program& program) = 0;
    // Sets the uniforms the pass's emit include needs on `program`. The frame calls it for
    // every further program drawn inside the pass (the fog emission of src/fog); a
    // technique's beginAccumulate() sets the same on the surface program.
    virtual void prepareProgram(int pass, const gpu::Program& program) const {
        (void)pass;
        (void)program;
    }
    // See PerPixelEmit. Compute needs the emit file written with OIT_TARGET / OIT_WRITE.
    virtual PerPixelEmit perPixelEmit(int pass) const {
        (void)pass;
        return PerPixelEmit::Fragments;
    }
    // Binds pass `pass`'s targets on image units VEIL_IMG_OIT_TARGET0 + location for the
    // compute emission (called after beginAccumulate() and prepareProgram(); the frame issues
    // the memory barriers after the dispatch).
    virtual void bindPerPixelEmit(int pass, const pass::Context& targets) const {
        (void)pass;
        (void)targets;
    }
    // Ends geometry pass `pass` (barriers, unbinding its images and framebuffer). Fixed-function
    // state needs no restoring: the next pass declares its own.
    virtual void endAccumulate(int pass) = 0;
    // Asked once after the last geometry pass: true makes the frame run all geometry passes
    // again (e.g. the `reference` node pool overflowed and was grown). A technique must not
    // ask for endless repeats.
    virtual bool repeatAccumulation() { return false; }
    // True when the technique keeps every surface of a pixel with its depth and can take the
    // fog piecewise (`reference`): the frame then marches the fog after the surfaces of the
    // last geometry pass, one contribution per segment between consecutive surfaces
    // (shaders/volume/fog_march.comp with FOG_SEGMENTS), instead of one contribution at a
    // representative depth. Its emit include then also defines, under OIT_FOG_SEGMENTS,
    //     uint oitSurfaceList(ivec2 p);   // handle to the pixel's surfaces stored so far
    //     float oitNextSurfaceDepth(uint list, float after); // nearest depth > after, or 1e30
    virtual bool fogSegments() const { return false; }
    // Composites the accumulation over targets.hdrColor.
    virtual void resolve(const pass::Context& targets) = 0;
    // How far (pixels) a pixel's result reads the accumulation and the opaque depth around it:
    // the viewer's tiled refinement (frame::Renderer::refineStep) accumulates a tile and this
    // margin around it, so that the tile comes out as in the whole frame. 0: the resolve reads
    // the pixel's own accumulation only.
    virtual int refineMarginPx() const { return 0; }
    // Bytes of technique-owned storage per pixel (memory reports, benchmarks).
    virtual std::size_t bytesPerPixel() const = 0;
    // The technique's own targets as frame resources (debug views, `veil render --dump`),
    // declared once: name "oit.<technique>.<target>", the texture behind it (null: none now)
    // and whether the resolve writes it (e.g. `reference`'s fragments per pixel) rather than
    // the transparent pass (the accumulation targets, which the resolve reads).
    struct Resource {
        std::string name;
        std::function<const gpu::Texture*()> texture;
        bool writtenByResolve = false;
    };
    virtual std::vector<Resource> resources() const { return {}; }
    // Counters of the last frame for reports and the viewer (e.g. `reference`'s node pool),
    // as a JSON object; empty for techniques that keep none.
    virtual nlohmann::json stats() const { return nlohmann::json::object(); }

    // The frame's two passes of the technique, `transparent` (every geometry pass: the
    // transparent surfaces, with what `hooks` adds) and `resolve`, scope Pixels, writing
    // oit.accumulation and resources() (src/oit/technique.cpp).
    struct GeometryHooks {
        // The transparent-surface program of geometry pass `pass` (the frame builds it with
        // the emit include and defines(pass)).
        std::function<const gpu::Program&(int pass)> surfaceProgram;
        // Inside geometry pass `pass`, after beginAccumulate() and before the surfaces (the
        // fog's per-pixel emission), and after the surfaces before endAccumulate() (the fog's
        // piecewise march); either may be null.
        std::function<void(const pass::Context&, int pass)> beforeSurfaces, afterSurfaces;
        // Resources the transparent pass reads besides the depth (fog.radiance, ao.visibility).
        std::vector<std::string> reads;
    };
    std::vector<pass::Pass> passes(GeometryHooks hooks);

    // The effective values of the technique's declared properties (Registry::create sets them).
    const Properties& properties() const { return properties_; }

private:
    template <class>
    friend class veil::NamedRegistry;
    Properties properties_;
};

struct TechniqueInfo {
    std::string name;
    std::string description;
    std::function<bool(const gpu::ContextInfo&)> isAvailable; // null = always
    // Creates the technique from validated, complete properties of `properties` below.
    std::function<std::unique_ptr<Technique>(gpu::ProgramManager&, const Properties&)> create;
    PropertySchema properties; // declared once: scene, --set, report, `veil techniques`
    // Runs on the compute rasterizer (render.oit_rasterizer = compute,
    // src/frame/stages/compute_raster.*): its emit file's OIT_COMPUTE form holds for surface fragments
    // (several per pixel, in order, from the pixel's one invocation).
    bool computeRaster = false;
};

// The OIT techniques as a kind of TechniqueRegistry (base/named_registry.h).
struct TechniqueKind {
    using Info = TechniqueInfo;
    using Technique = oit::Technique;
    using Context = gpu::ContextInfo;
    using Programs = gpu::ProgramManager;
    static constexpr const char* kName = "OIT technique";
    static constexpr const char* kWhere = "render.oit";
    // A technique's own checks of its properties (moment: z_min < z_max) name `where`.
    static constexpr bool kErrorsNameWhere = true;
    static void registerBuiltins(TechniqueRegistry<TechniqueKind>& registry); // registry.cpp
};

// Technique ids in one registry: find, names, get and resolve; create() makes a technique from
// validated properties.
using Registry = TechniqueRegistry<TechniqueKind>;

} // namespace veil::oit
