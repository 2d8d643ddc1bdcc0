// The technique catalogue (techniques.h).
#include "catalog/techniques.h"

#include "integrators/registry.h"
#include "oit/technique.h"
#include "shadows/technique.h"

namespace veil::catalog {

namespace {

template <class R>
void collect(const R& registry, const std::string& kind, std::vector<Technique>& out) {
    for (const auto& t : registry.all())
        out.push_back({kind, t.name, t.description, t.isAvailable, &t.properties});
}

} // namespace

std::vector<Technique> techniques() {
    std::vector<Technique> all;
    collect(oit::Registry::instance(), "oit", all);
    collect(shadows::Registry::instance(), "shadows", all);
    const auto& integrators = volume::IntegratorRegistry::instance();
    for (const std::string& name : integrators.names()) {
        const volume::IntegratorInfo& i = integrators.get(name);
        all.push_back({"integrator", i.name, i.description, nullptr, &i.properties, true});
    }
    return all;
}

std::string availability(const Technique& t, const std::optional<gpu::ContextInfo>& info) {
    if (t.cpu) return "yes (CPU)";
    if (!info) return "unknown (no GL context)";
    if (!t.isAvailable || t.isAvailable(*info)) return "yes";
    return "no";
}

nlohmann::json techniqueJson(const Technique& t, const std::optional<gpu::ContextInfo>& info) {
    return {{"kind", t.kind},
            {"name", t.name},
            {"description", t.description},
            {"available", availability(t, info)},
            {"properties", t.properties->describe()}};
}

nlohmann::json catalogJson(const std::optional<gpu::ContextInfo>& info) {
    nlohmann::json out = nlohmann::json::array();
    for (const Technique& t : techniques())
        out.push_back(techniqueJson(t, info));
    return out;
}

} // namespace veil::catalog
