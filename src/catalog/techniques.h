// The catalogue of registered techniques of every kind (OIT, shadows, the CPU integrators of
// --integrator): names, descriptions, declared properties and whether a GL driver has them. `veil
// techniques` prints it and the Python module's veil.techniques() returns it.
#pragma once

#include "base/properties.h"
#include "gpu/context.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace veil::catalog {

struct Technique {
    std::string kind; // "oit", "shadows" (the render key it is chosen with), "integrator"
    std::string name, description;
    std::function<bool(const gpu::ContextInfo&)> isAvailable; // null: always
    const PropertySchema* properties = nullptr;
    bool cpu = false; // runs on the CPU: available whatever the GL driver
};

// Every registered technique: the OIT ones, the shadow ones, then the CPU integrators, each
// in registry order.
std::vector<Technique> techniques();

// "yes" or "no" on the driver of `info`, "unknown (no GL context)" without one; "yes (CPU)"
// for a CPU integrator.
std::string availability(const Technique& t, const std::optional<gpu::ContextInfo>& info);

// {kind, name, description, available, properties (PropertySchema::describe())}.
nlohmann::json techniqueJson(const Technique& t, const std::optional<gpu::ContextInfo>& info);

// techniqueJson of every technique, in techniques() order.
nlohmann::json catalogJson(const std::optional<gpu::ContextInfo>& info);

} // namespace veil::catalog
