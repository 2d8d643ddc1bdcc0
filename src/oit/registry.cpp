#include "oit/technique.h"

#include "base/error.h"
#include "oit/blend/blend.h"
#include "oit/moment/moment.h"
#include "oit/phenomenological/phenomenological.h"
#include "oit/reference/reference.h"
#include "oit/stochastic/stochastic.h"
#include "oit/wboit/wboit.h"

#include <fmt/ranges.h>

namespace veil::oit {

namespace {
void registerBuiltinTechniques(Registry& registry) {
    registerBlend(registry);
    registerReference(registry);
    registerWboit(registry);
    registerPhenomenological(registry);
    registerStochastic(registry);
    registerMoment(registry);
}
} // namespace

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

} // namespace veil::oit
