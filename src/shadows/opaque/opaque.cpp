#include "shadows/opaque/opaque.h"

#include "shadows/common/depth_maps.h"

#include <fmt/format.h>

namespace veil::shadows {

namespace {

class OpaqueTechnique final : public Technique {
public:
    OpaqueTechnique(gpu::ProgramManager& programs, const Properties& p)
        : depth_(programs), bias_(p.getFloat("bias")), pcfRadius_(p.getInt("pcf_radius")) {}

    std::string name() const override { return "opaque"; }
    std::filesystem::path visibilityInclude() const override {
        return "shadows/opaque/visibility.glsl";
    }
    void resize(int mapSize, int viewCount) override { depth_.resize(mapSize, viewCount); }
    std::vector<pass::Pass> passes() override {
        return {{"",
                 {},
                 {"shadow.depth"},
                 [this](const pass::Context& f) { depth_.render(f); },
                 [this](const pass::Context& f, int y0, int y1) { depth_.renderRows(f, y0, y1); }}};
    }
    std::vector<std::string> receiverResources() const override { return {"shadow.depth"}; }
    void bindForReceivers() const override { depth_.bind(); }
    void fillParams(ShadowsBlock& block) const override {
        block.params[0] = glm::vec4(bias_, static_cast<float>(pcfRadius_), 0.0f, 0.0f);
    }
    const gpu::Texture* resourceTexture(const std::string& name) const override {
        return name == "shadow.depth" ? &depth_.texture() : nullptr;
    }
    // The casters' depth from each light view (fitted to the scene bounds): no camera.
    bool dependsOnCamera() const override { return false; }
    std::size_t gpuBytes() const override { return depth_.gpuBytes(); }

private:
    DepthMaps depth_;
    float bias_;
    int pcfRadius_;
};

} // namespace

PropertySchema& addOpaqueMapProperties(PropertySchema& schema) {
    schema.real("bias", 0.01, 0.0, 1e6,
                "opaque map depth bias in world units along the light axis (slope-scaled on "
                "surfaces; each PCF tap also follows the receiver plane)",
                "[Isidoro06]");
    schema.integer("pcf_radius", 1, 0, 16, "opaque map PCF kernel: (2r+1)^2 taps");
    schema.choice("receiver_slope", "derivatives",
                  {"derivatives", "geometric", "none", "plane-bias"},
                  "where the receiver plane's depth slope of the opaque map comes from, "
                  "compiled into the receiving programs (an edit builds a new renderer): "
                  "derivatives = the screen-space derivatives of the shaded point in fragment "
                  "shaders (zero where degenerate; geometric in compute receivers), "
                  "geometric = two tangents of the normal's plane projected per light "
                  "everywhere, none = no slope (acne on tilted receivers; for measuring its "
                  "cost), plane-bias = the derivatives' slope as one bias for every tap (the "
                  "plane's depth change over the kernel: more light leaks at contacts, fewer "
                  "operations per tap)",
                  "[Isidoro06]");
    return schema;
}

std::vector<std::string> opaqueMapDefines(const Properties& properties) {
    const std::string mode = properties.values().contains("receiver_slope")
                                 ? properties.getString("receiver_slope")
                                 : std::string("derivatives");
    return {fmt::format("VEIL_RECEIVER_SLOPE {}", mode == "geometric"    ? 1
                                                  : mode == "none"       ? 2
                                                  : mode == "plane-bias" ? 3
                                                                         : 0)};
}

void registerOpaque(Registry& registry) {
    PropertySchema schema = commonProperties();
    addOpaqueMapProperties(schema);
    registry.add({"opaque",
                  "Williams depth maps of the opaque casters with PCF; transparent casters and "
                  "fog cast no shadow (the baseline)",
                  nullptr,
                  [](gpu::ProgramManager& programs, const Properties& p) {
                      return std::make_unique<OpaqueTechnique>(programs, p);
                  },
                  std::move(schema)});
}

} // namespace veil::shadows
