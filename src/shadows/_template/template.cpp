#include "shadows/_template/template.h"

#include "shadows/common/depth_maps.h"
#include "shadows/opaque/opaque.h"

namespace veil::shadows {

namespace {

class TemplateTechnique final : public Technique {
public:
    TemplateTechnique(gpu::ProgramManager& programs, const Properties& p)
        : depth_(programs), bias_(p.getFloat("bias")), pcfRadius_(p.getInt("pcf_radius")),
          strength_(p.getFloat("strength")) {}

    std::string name() const override { return "template"; }
    // "veil:light_visibility" of this technique: lightAttenuate() and lightAttenuateInMedium().
    std::filesystem::path visibilityInclude() const override {
        return "shadows/_template/visibility.glsl";
    }

    // One layer per light view in every texture array (maps of the technique's own are created
    // here too).
    void resize(int mapSize, int viewCount) override { depth_.resize(mapSize, viewCount); }

    // The frame adds these in order as "shadow" and "shadow.<name>", with their resources.
    // A technique with maps of its own adds a pass here, e.g.
    //   {"filter", {"shadow.depth"}, {"shadow.<name>"}, [this](const pass::Context& f) {...}}
    // applying a declared gpu::PipelineState through f.state before each draw or clear.
    std::vector<pass::Pass> passes() override {
        return {{"",
                 {},
                 {"shadow.depth"},
                 [this](const pass::Context& f) { depth_.render(f); },
                 [this](const pass::Context& f, int y0, int y1) { depth_.renderRows(f, y0, y1); }}};
    }
    std::vector<std::string> receiverResources() const override { return {"shadow.depth"}; }
    void bindForReceivers() const override { depth_.bind(); }

    // params[0] is the opaque map's (bias, PCF radius), read by opaque_depth.glsl; params[1..3]
    // are the technique's own.
    void fillParams(ShadowsBlock& block) const override {
        block.params[0] = glm::vec4(bias_, static_cast<float>(pcfRadius_), 0.0f, 0.0f);
        block.params[1] = glm::vec4(strength_, 0.0f, 0.0f, 0.0f);
    }
    const gpu::Texture* resourceTexture(const std::string& name) const override {
        return name == "shadow.depth" ? &depth_.texture() : nullptr;
    }
    // The maps depend only on the light views and the casters, so the viewer may keep them.
    bool dependsOnCamera() const override { return false; }
    std::size_t gpuBytes() const override { return depth_.gpuBytes(); }
    nlohmann::json stats() const override { return {{"strength", strength_}}; }

private:
    DepthMaps depth_;
    float bias_;
    int pcfRadius_;
    float strength_;
};

} // namespace

void registerTemplate(Registry& registry) {
    PropertySchema schema = commonProperties();
    addOpaqueMapProperties(schema);
    schema.real("strength", 1.0, 0.0, 1.0,
                "fraction of the light an opaque caster blocks (1: Williams depth maps, 0: none)",
                "[Williams78]");
    registry.add({"template", "copy me: opaque depth maps with a shadow strength property", nullptr,
                  [](gpu::ProgramManager& programs, const Properties& p) {
                      return std::make_unique<TemplateTechnique>(programs, p);
                  },
                  std::move(schema)});
}

} // namespace veil::shadows
