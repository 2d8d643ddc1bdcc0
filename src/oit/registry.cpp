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

void Registry::add(TechniqueInfo info) {
    VEIL_CHECK(!find(info.name), "OIT technique '{}' registered twice", info.name);
    techniques_.push_back(std::move(info));
}

const TechniqueInfo* Registry::find(const std::string& name) const {
    for (const auto& t : techniques_)
        if (t.name == name) return &t;
    return nullptr;
}

std::vector<std::string> Registry::names() const {
    std::vector<std::string> n;
    for (const auto& t : techniques_)
        n.push_back(t.name);
    return n;
}

const TechniqueInfo& Registry::get(const std::string& name, const std::string& where) const {
    const TechniqueInfo* info = find(name);
    VEIL_CHECK(info, "{}unknown OIT technique '{}' (known: {})", where.empty() ? "" : where + ": ",
               name, fmt::join(names(), ", "));
    return *info;
}

Properties Registry::resolve(const std::string& name, const nlohmann::json& values,
                             const std::string& where) const {
    return get(name, where.empty() ? where : where + "/type")
        .properties.resolve(values, where, fmt::format("OIT technique '{}'", name));
}

std::unique_ptr<Technique> Registry::create(const std::string& name,
                                            const gpu::ContextInfo& context,
                                            gpu::ProgramManager& programs,
                                            const nlohmann::json& values,
                                            const std::string& where) const {
    const TechniqueInfo& info = get(name, where.empty() ? where : where + "/type");
    Properties properties = resolve(name, values, where);
    VEIL_CHECK(!info.isAvailable || info.isAvailable(context),
               "OIT technique '{}' is not available on this GL driver ({})", name,
               context.renderer);
    std::unique_ptr<Technique> technique = info.create(programs, properties);
    technique->properties_ = std::move(properties);
    return technique;
}

} // namespace veil::oit
