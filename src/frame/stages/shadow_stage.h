// The frame's first stage: the shadow technique (src/shadows) of the frame's shadow-casting
// lights, scope Lights. Its passes (`shadow`, `shadow.<pass>`, and `voxelize.light_slices`
// before them when the technique asks for a light slice map) draw maps of every view of every
// shadow-casting light; receivers (passes with pass::Pass::receivesShadows) read the
// technique's receiver resources. Each frame it refits the light views to the bounds of
// casters and receivers and fills the shadows uniform block.
//
// Map reuse (the viewer, docs/viewer.md "Slow drivers"): with reuse on and a technique whose
// maps do not depend on the camera (shadows::Technique::dependsOnCamera), a frame skips the
// shadow passes while the maps of an earlier frame are valid (Reuse below; frame::Renderer
// documents what invalidates them).
#pragma once

#include "gpu/context.h"
#include "gpu/objects.h"
#include "pass/stage.h"
#include "scene/scene.h"
#include "shadows/technique.h"
#include "shadows/views.h"
#include "voxelize/light_slice_map.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace veil::frame {

class ShadowStage : public pass::Stage {
public:
    // `where` names where the technique's properties came from (errors about its limits).
    ShadowStage(const scene::Scene& scene, const gpu::ContextInfo& context,
                gpu::ProgramManager& programs, std::unique_ptr<shadows::Technique> technique,
                const std::string& where);

    std::string name() const override { return "shadows"; }
    std::vector<pass::Pass> passes(const pass::Assembly& assembly) override;
    void addResources(pass::Resources& resources) const override;
    std::size_t gpuBytes() const override;
    // Refits the views (lights and objects may move), fills the shadows block, and gives the
    // context the views and the receivers' uniforms.
    void beginFrame(pass::Context& context) override;
    // Binds the shadows block (every call that runs passes: state may have changed between).
    void bindUniforms() const;

    // The world bounds the views are fitted to: the scene's objects, widened by the media.
    void setBounds(glm::vec3 lo, glm::vec3 hi) {
        lo_ = lo;
        hi_ = hi;
    }
    bool casting() const { return set_.viewCount > 0; }
    const shadows::Technique& technique() const { return *technique_; }
    const shadows::ShadowLightSet& lights() const { return set_; }
    const std::vector<shadows::LightView>& views() const { return views_; }
    int mapSize() const { return mapSize_; }
    // What receivers read, and their binding before a receiving pass.
    const std::vector<std::string>& receiverResources() const { return receiverResources_; }
    void bindForReceivers() const;

    struct Reuse {
        bool enabled = false;
        bool valid = false; // the maps hold what the shadow passes would draw now
        bool skip = false;  // this frame's decision (decide())
        std::uint64_t renders = 0, reuses = 0;
    };
    Reuse& reuse() { return reuse_; }
    const Reuse& reuse() const { return reuse_; }
    // This frame's decision: skip the passes when reuse is on, the maps are valid and do not
    // depend on the camera, and there are passes to skip.
    bool decide(bool hasPasses);

private:
    const scene::Scene& scene_;
    std::unique_ptr<shadows::Technique> technique_;
    std::unique_ptr<voxelize::LightSliceMap> lightSlices_;
    shadows::ShadowLightSet set_;
    std::vector<shadows::LightView> views_;
    std::vector<std::string> receiverResources_;
    std::vector<std::string> writes_; // by the technique's passes
    int mapSize_ = 0;
    glm::vec3 lo_{0.0f}, hi_{0.0f};
    gpu::Buffer ubo_;
    Reuse reuse_;
};

} // namespace veil::frame
