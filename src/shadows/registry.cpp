#include "shadows/technique.h"

#include "shadows/moment/moment.h"
#include "shadows/opaque/opaque.h"
#include "shadows/reference/reference.h"
#include "shadows/stochastic/stochastic.h"
#include "shadows/transmittance_slicemap/transmittance_slicemap.h"
#include "shadows/volume/volume.h"

namespace veil::shadows {

void TechniqueKind::registerBuiltins(Registry& registry) {
    registerOpaque(registry);
    registerMoment(registry);
    registerReference(registry);
    registerTransmittanceSlicemap(registry);
    registerStochastic(registry);
    registerVolume(registry);
}

Technique::Receivers Technique::receivers() const {
    return {visibilityInclude(), opaqueMapDefines(properties())};
}

PropertySchema commonProperties(int defaultSize) {
    PropertySchema s;
    s.integer("size", defaultSize, 16, 16384,
              "texels per side of each light view's map (a point light has six)");
    s.integer("max_lights", 4, 1, VEIL_MAX_LIGHTS,
              "most shadow-casting lights; more is an error naming the scene, not a silent "
              "drop");
    return s;
}

} // namespace veil::shadows
