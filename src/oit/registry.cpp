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
    try {
        return createTechnique(name, context, programs, values, where);
    } catch (const Error& e) {
        // A technique's own checks of its properties (moment: z_min < z_max) know no file:
        // name where the properties came from, unless the message already does.
        const std::string what = e.what();
        if (where.empty() || what.rfind(where, 0) == 0 || what.find(where) != std::string::npos)
            throw;
        throw Error(fmt::format("{}: {}", where, what));
    }
}

} // namespace veil::oit
