#include "frame/stages/shadow_stage.h"

#include "frame/frame_setup.h"

#include <fmt/format.h>

namespace veil::frame {

ShadowStage::ShadowStage(const scene::Scene& scene, const gpu::ContextInfo& context,
                         gpu::ProgramManager& programs,
                         std::unique_ptr<shadows::Technique> technique, const std::string& where)
    : scene_(scene), technique_(std::move(technique)) {
    const Properties& p = technique_->properties();
    set_ = shadows::chooseShadowLights(scene, p.getInt("max_lights"),
                                       fmt::format("{} (max_lights)", where));
    mapSize_ = p.getInt("size");
    if (set_.viewCount > 0) {
        checkShadowWork(scene, context, *technique_, where, mapSize_, set_.viewCount);
        technique_->resize(mapSize_, set_.viewCount);
        if (auto request = technique_->lightSliceMap())
            lightSlices_ = std::make_unique<voxelize::LightSliceMap>(programs, std::move(*request));
        receiverResources_ = technique_->receiverResources();
    }
    ubo_.setStorage(sizeof(shadows::ShadowsBlock), nullptr);
}

std::vector<pass::Pass> ShadowStage::passes(const pass::Assembly&) {
    std::vector<pass::Pass> out;
    if (set_.viewCount == 0) return out;
    // The light slice map the technique reads, voxelized first (src/voxelize).
    if (lightSlices_)
        out.push_back({"voxelize.light_slices",
                       {},
                       {lightSlices_->request().name},
                       [this](const pass::Context& context) {
                           std::vector<voxelize::LightSliceMap::View> views;
                           for (const shadows::LightView& v : *context.lightViews)
                               views.push_back({v.layer, v.view, v.viewProjection});
                           lightSlices_->render(context, views);
                       }});
    for (pass::Pass& p : technique_->passes()) {
        p.name = p.name.empty() ? "shadow" : "shadow." + p.name;
        out.push_back(std::move(p));
    }
    writes_.clear();
    for (pass::Pass& p : out) {
        p.scope = pass::Scope::Lights;
        if (&p != &out.front() || !lightSlices_)
            writes_.insert(writes_.end(), p.writes.begin(), p.writes.end());
    }
    return out;
}

void ShadowStage::addResources(pass::Resources& resources) const {
    if (set_.viewCount == 0) return;
    if (lightSlices_) lightSlices_->addResources(resources);
    for (const std::string& w : writes_) // the technique's passes' (passes())
        resources.add(w, [this, w] { return technique_->resourceTexture(w); });
}

std::size_t ShadowStage::gpuBytes() const {
    return set_.viewCount > 0 ? technique_->gpuBytes() : 0;
}

void ShadowStage::beginFrame(pass::Context& context) {
    views_ = shadows::fitViews(scene_, set_, lo_, hi_);
    shadows::ShadowsBlock block{};
    shadows::fillShadowsBlock(block, views_, set_, mapSize_);
    technique_->fillParams(block);
    ubo_.setSubData(0, sizeof(block), &block);
    context.lightViews = &views_;
    context.prepareReceiver = nullptr;
    if (set_.viewCount > 0)
        context.prepareReceiver = [this, &context](const gpu::Program& program) {
            technique_->prepareReceiver(program, context);
        };
}

void ShadowStage::bindUniforms() const { ubo_.bindBase(GL_UNIFORM_BUFFER, VEIL_UBO_SHADOWS); }

void ShadowStage::bindForReceivers() const {
    if (set_.viewCount > 0) technique_->bindForReceivers();
}

bool ShadowStage::decide(bool hasPasses) {
    reuse_.skip = reuse_.enabled && reuse_.valid && hasPasses && !technique_->dependsOnCamera();
    return reuse_.skip;
}

} // namespace veil::frame
