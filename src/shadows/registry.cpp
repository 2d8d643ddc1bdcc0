#include "shadows/technique.h"

#include "base/error.h"
#include "shadows/moment/moment.h"
#include "shadows/opaque/opaque.h"
#include "shadows/reference/reference.h"
#include "shadows/stochastic/stochastic.h"
#include "shadows/transmittance_slicemap/transmittance_slicemap.h"
#include "shadows/volume/volume.h"

namespace veil::shadows {

namespace {
void registerBuiltinTechniques(Registry& registry) {
    registerOpaque(registry);
    registerMoment(registry);
    registerReference(registry);
    registerTransmittanceSlicemap(registry);
    registerStochastic(registry);
    registerVolume(registry);
}
} // namespace

PropertySchema commonProperties(int defaultSize) {
    PropertySchema s;
    s.integer("size", defaultSize, 16, 16384,
              "texels per side of each light view's map (a point light has six)");
    s.integer("max_lights", 4, 1, VEIL_MAX_LIGHTS,
              "most shadow-casting lights; more is an error naming the scene, not a silent "
              "drop");
    return s;
}

Registry& Registry::instance() {
    static Registry* registry = [] {
        auto* r = new Registry();
        registerBuiltinTechniques(*r);
        return r;
    }();
    return *registry;
}

std::unique_ptr<Technique> Registry::create(const std::string& name,
                                            const gpu::ContextInfo& context,
                                            gpu::ProgramManager& programs,
                                            const nlohmann::json& values,
                                            const std::string& where) const {
    return createTechnique(name, context, programs, values, where);
}

} // namespace veil::shadows
