// frame::Renderer's pass list: the modules' declared passes concatenated in frame order, and
// the frame's own (depth pre-pass, opaque, tonemap).
#include "frame/renderer.h"

namespace veil::frame {

void Renderer::addPass(pass::Pass p) {
    // A receiver reads the shadow technique's maps (after the depth where it reads that).
    if (p.receivesShadows) {
        const auto at = p.reads.begin() + (!p.reads.empty() && p.reads.front() == "depth");
        p.reads.insert(at, shadowResources_.begin(), shadowResources_.end());
    }
    passes_.add(std::move(p));
}

void Renderer::buildPasses() {
    resources_.clear();
    resources_.add("depth", depth_);
    resources_.add("hdr", hdr_);
    resources_.add("ldr", ldr_);
    // The shadow technique's passes, when a light casts shadows.
    shadowResources_.clear();
    if (shadowSet_.viewCount > 0) {
        shadowResources_ = shadows_->receiverResources();
        // The light slice map the technique reads, voxelized first (src/voxelize).
        if (lightSlices_) {
            pass::Pass p{"voxelize.light_slices",
                         {},
                         {lightSlices_->request().name},
                         [this](const pass::Context& context) {
                             std::vector<voxelize::LightSliceMap::View> views;
                             for (const shadows::LightView& v : *context.lightViews)
                                 views.push_back({v.layer, v.view, v.viewProjection});
                             lightSlices_->render(context, views);
                         }};
            p.scope = pass::Scope::Lights;
            lightSlices_->addResources(resources_);
            addPass(std::move(p));
        }
        for (pass::Pass& p : shadows_->passes()) {
            p.name = p.name.empty() ? "shadow" : "shadow." + p.name;
            p.scope = pass::Scope::Lights;
            for (const std::string& w : p.writes)
                resources_.add(w, [this, w] { return shadows_->resourceTexture(w); });
            addPass(std::move(p));
        }
    }
    std::vector<std::string> aoReads;
    if (ao_) {
        addPass({"depth", {}, {"depth"}, [this](const pass::Context&) { opaque(true); }});
        for (pass::Pass& p : ao_->passes())
            addPass(std::move(p));
        ao_->addResources(resources_);
        aoReads = {"ao.visibility"};
    }
    pass::Pass opaquePass{
        "opaque", aoReads, {"depth", "hdr"}, [this](const pass::Context&) { opaque(false); }};
    opaquePass.receivesShadows = true;
    addPass(std::move(opaquePass));

    std::vector<std::string> transparentReads = aoReads; // inferred AO [McGuire17 Listing 2]
    if (fog_) {
        for (pass::Pass& p : fog_->passes(kRefineLightSlabTexels))
            addPass(std::move(p));
        fog_->addResources(resources_);
        transparentReads.push_back("fog.radiance");
    }
    oit::Technique::GeometryHooks hooks =
        transparencyHooks(*oit_, fog_.get(), programs_, transparency_, transparentReads);
    for (pass::Pass& p : computeRaster_ ? computeRaster_->passes(*oit_, std::move(hooks))
                                        : oit_->passes(std::move(hooks)))
        addPass(std::move(p));
    for (const oit::Technique::Resource& r : oit_->resources())
        resources_.add(r.name, r.texture);

    pass::Pass tonemap{
        "tonemap", {"hdr"}, {"ldr"}, [this](const pass::Context& context) {
            const glm::ivec4 r = context.region;
            const gpu::Program& program = programs_.get(tonemapProgram_);
            program.use();
            program.set("exposure", scene_.render.exposure)
                .set("operatorId", scene_.render.tonemap == "clamp" ? 1 : 0)
                .set("region", r);
            hdr_.bind(VEIL_TEX_HDR);
            glBindImageTexture(VEIL_IMG_OUTPUT, ldr_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
            glDispatchCompute((r.z - r.x + 7) / 8, (r.w - r.y + 7) / 8, 1);
            glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        }};
    tonemap.scope = pass::Scope::Pixels;
    addPass(std::move(tonemap));
    passes_.validate();
}

// The opaque objects into hdr and depth, or (depthOnly: AO's pre-pass) their depth alone: the
// same program with its colour masked and its shading skipped, so the shaded pass's GL_LEQUAL
// test passes exactly where the pre-pass wrote.
void Renderer::opaque(bool depthOnly) {
    opaqueFbo_.bind();
    gpu::PipelineState state;
    state.view(width_, height_).depth(depthOnly || !ao_ ? GL_LESS : GL_LEQUAL, true);
    if (depthOnly) state.colorMask[0] = glm::bvec4(false);
    state_.apply(state); // before the clears: they obey the colour/depth masks
    const glm::vec4 bg(scene_.render.background, 1.0f);
    const float one = 1.0f;
    if (!depthOnly) glClearNamedFramebufferfv(opaqueFbo_.id(), GL_COLOR, 0, &bg.x);
    if (depthOnly || !ao_) glClearNamedFramebufferfv(opaqueFbo_.id(), GL_DEPTH, 0, &one);
    const gpu::Program& program = programs_.get(opaqueProgram_);
    program.set("useOverride", 0);
    if (depthOnly) {
        program.set("depthPrepass", 1);
    } else if (ao_) {
        program.set("depthPrepass", 0);
        ao_->visibility().bind(VEIL_TEX_AO);
    }
    if (!depthOnly && pass_.prepareReceiver) pass_.prepareReceiver(program);
    drawObjects(scene_, meshes_, program, pass::ObjectSet::Opaque);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

const gpu::Texture* Renderer::resourceTexture(const std::string& name) const {
    return resources_.texture(name);
}

} // namespace veil::frame
