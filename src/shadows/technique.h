// The shadow interface (docs/architecture.md "One frame: passes and resources"): a shadow technique
// owns its maps for every view of every shadow-casting light (src/shadows/views.h), renders them in
// its passes, and provides the GLSL file defining
//     void lightAttenuate(int light, vec3 P, vec3 N, vec3 L, inout vec3 radiance);
//     void lightAttenuateInMedium(int light, vec3 P, inout vec3 radiance);
//     vec3 lightVisibility(int light, vec3 P, vec3 N, vec3 L);
//     vec3 lightVisibilityInMedium(int light, vec3 P);
// which every receiver includes as "veil:light_visibility": opaque and transparent surfaces
// (shaders/frame/shading.glsl) and the fog marcher's in-scattering. So one technique gives
// every receiver the same answer.
//
// Techniques are registered by name in one registry (src/shadows/registry.cpp) with their
// properties declared once (src/base/properties.h); every technique declares the common ones
// of commonProperties() (map size, max_lights) first.
#pragma once

#include "base/named_registry.h"
#include "base/properties.h"
#include "gpu/context.h"
#include "gpu/objects.h"
#include "gpu/pipeline_state.h"
#include "gpu/shader.h"
#include "pass/pass.h"
#include "scene/scene.h"
#include "shadows/views.h"

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace veil::shadows {

// A technique's passes are pass::Pass (src/pass/pass.h), run with the frame's pass::Context:
// the frame adds them first, scope Lights, as "shadow" (the first) or "shadow.<name>".
// Resources are named "shadow.<what>" (shadow.depth is the opaque casters' depth array). The
// context gives the passes lightViews (one layer of the maps each), the scene (materials of the
// casters), the state tracker, drawObjects (ObjectSet::OpaqueCasters / TransparentCasters: the
// caller sets `viewProjection`, `useOverride` = 1 and `billboardAxes`, particles face the
// light), bindMedia (null without grid volumes), the seed, and the camera (screen-space
// techniques, e.g. `volume`: width, height, viewProjection, orthographicCamera). A pass may run
// in bands of map rows (pass::Pass::executeRows, rows = the map size).

class Technique {
public:
    virtual ~Technique() = default;
    virtual std::string name() const = 0;
    // GLSL file (relative to shaders/) of "veil:light_visibility".
    virtual std::filesystem::path visibilityInclude() const = 0;
    // Called when the number of views or the map size changes: (re)creates the texture arrays
    // with one layer per view.
    virtual void resize(int mapSize, int viewCount) = 0;
    // The light slice map the technique's passes or receivers read, if any: the frame then
    // adds a voxelize pass writing it (the resource request.name) before passes(). Called
    // once, after the first resize().
    virtual std::optional<pass::LightSliceMapRequest> lightSliceMap() { return std::nullopt; }
    // The passes, in order. The frame's receivers read `receiverResources()`.
    virtual std::vector<pass::Pass> passes() = 0;
    virtual std::vector<std::string> receiverResources() const = 0;
    // Binds the textures the visibility include samples (VEIL_TEX_SHADOW_MAP, _SHADOW1..3);
    // called before every receiving pass.
    virtual void bindForReceivers() const = 0;
    // Sets what the visibility include needs on a receiver's program (opaque and transparent
    // surfaces, the fog marcher) before it draws: e.g. frame.bindMedia(program) for an include
    // that marches the density toward the light. Most techniques need nothing beyond the
    // textures of bindForReceivers() and the shadows block.
    virtual void prepareReceiver(const gpu::Program& program, const pass::Context& frame) const {
        (void)program;
        (void)frame;
    }
    // The technique's params[4] of the shadows block (views.glsl), read by its include.
    virtual void fillParams(ShadowsBlock& block) const = 0;
    // True when the maps hold the absorbance of the grid density volumes, so the fog marcher
    // must not multiply its own self-shadowing volumes (src/fog) in again. (Global
    // homogeneous fog stays analytic in the marcher.)
    virtual bool attenuatesMedia() const { return false; }
    // Throws veil::Error naming the limit when the receivers' work on this driver would exceed
    // one of its limits and come out silently wrong (e.g. `reference`'s media march against
    // Mesa's loop iterations per invocation); `fogSteps` is the fog marcher's steps per pixel
    // (0 without grid volumes), `lights` the shadowed lights, `where` the scene.
    virtual void checkReceiverWork(const gpu::ContextInfo& context, int fogSteps, int lights,
                                   const std::string& where) const {
        (void)context;
        (void)fogSteps;
        (void)lights;
        (void)where;
    }
    // Whether the maps depend on the camera (context width/height, viewProjection,
    // orthographicCamera, the camera block in the technique's passes). A technique that says
    // false promises that its passes write the same maps for every camera as long as the
    // lights, the casters (geometry, transforms, materials), the media, its properties and
    // its shaders are unchanged: the viewer then keeps them across frames
    // (frame::Renderer::setReuseShadowMaps). True, the conservative default, redraws them
    // every frame (screen-space techniques such as `volume`).
    virtual bool dependsOnCamera() const { return true; }
    // The texture behind one of the technique's resources (debug views, dumps), or null.
    virtual const gpu::Texture* resourceTexture(const std::string& name) const {
        (void)name;
        return nullptr;
    }
    virtual std::size_t gpuBytes() const = 0;
    // Samples the technique's own passes take per frame at this map size and view count
    // (e.g. density samples of a fog optical-depth pass), with a one-line breakdown for
    // messages; {0, ""} when they are bounded by the map size alone. The frame checks it
    // against render.fog_sample_limit before resize() allocates anything.
    struct WorkEstimate {
        double samples = 0.0;
        std::string breakdown;
    };
    virtual WorkEstimate work(int mapSize, int viewCount, bool media) const {
        (void)mapSize;
        (void)viewCount;
        (void)media;
        return {};
    }
    // Counters of the last frame (JSON object) for reports and the viewer.
    virtual nlohmann::json stats() const { return nlohmann::json::object(); }

    const Properties& properties() const { return properties_; }
    // What the frame's surface receivers are compiled with (opaque.frag, transparent.frag, the
    // compute rasterizer's fine pass): the visibility include and the defines of the receiver
    // options, e.g. "VEIL_RECEIVER_SLOPE 2" for receiver_slope = none (opaque_depth.glsl).
    // Edits of those properties build a new renderer, so the programs follow them.
    struct Receivers {
        std::filesystem::path visibility; // "veil:light_visibility"
        std::vector<std::string> defines;
    };
    Receivers receivers() const;

private:
    template <class>
    friend class veil::NamedRegistry;
    Properties properties_;
};

struct TechniqueInfo {
    std::string name;
    std::string description;
    std::function<bool(const gpu::ContextInfo&)> isAvailable; // null = always
    std::function<std::unique_ptr<Technique>(gpu::ProgramManager&, const Properties&)> create;
    PropertySchema properties;
};

// The properties every shadow technique declares first: size (texels per side of every
// view's map), max_lights (more shadow-casting lights than this is an error).
PropertySchema commonProperties(int defaultSize = 2048);

// The shadow techniques as a kind of TechniqueRegistry (base/named_registry.h).
struct TechniqueKind {
    using Info = TechniqueInfo;
    using Technique = shadows::Technique;
    using Context = gpu::ContextInfo;
    using Programs = gpu::ProgramManager;
    static constexpr const char* kName = "shadow technique";
    static constexpr const char* kWhere = "render.shadows";
    static constexpr bool kErrorsNameWhere = false;
    static void registerBuiltins(TechniqueRegistry<TechniqueKind>& registry); // registry.cpp
};

// Technique ids in one registry: find, names, get and resolve; create() makes a technique from
// validated properties.
using Registry = TechniqueRegistry<TechniqueKind>;

} // namespace veil::shadows
