#include "oit/technique.h"

#include "oit/blend/blend.h"
#include "oit/moment/moment.h"
#include "oit/phenomenological/phenomenological.h"
#include "oit/reference/reference.h"
#include "oit/stochastic/stochastic.h"
#include "oit/wboit/wboit.h"

namespace veil::oit {

void TechniqueKind::registerBuiltins(Registry& registry) {
    registerBlend(registry);
    registerReference(registry);
    registerWboit(registry);
    registerPhenomenological(registry);
    registerStochastic(registry);
    registerMoment(registry);
}

} // namespace veil::oit
