// `veil techniques [NAME]`: every registered technique with its declared properties
// (key, type, default, range, doc, paper citation) and whether this GL driver has it.
#include "app/cli_checks.h"
#include "app/commands.h"

#include "base/error.h"
#include "base/suggest.h"
#include "catalog/techniques.h"
#include "gpu/context.h"

#include <fmt/ranges.h>

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <optional>

namespace veil::app {

namespace {

struct TechniquesArgs {
    std::string name;
    bool json = false;
    int device = -1;
};

std::string valueText(const nlohmann::json& v) {
    if (v.is_number_float()) return fmt::format("{:g}", v.get<double>());
    if (v.is_array()) {
        std::string out = "[";
        for (std::size_t i = 0; i < v.size(); ++i)
            out += (i ? ", " : "") + valueText(v[i]);
        return out + "]";
    }
    return v.is_string() ? v.get<std::string>() : v.dump();
}

void printProperties(const PropertySchema& properties) {
    if (properties.empty()) std::cout << "  no properties\n";
    for (const PropertyDecl& d : properties.all()) {
        std::cout << fmt::format("  {:<24} {:<6} default {}", d.key, propertyTypeName(d.type),
                                 valueText(d.defaultValue));
        if (const std::string range = d.rangeText(); !range.empty())
            std::cout << "  range " << range;
        std::cout << "\n      " << d.doc;
        if (!d.citation.empty()) std::cout << "  " << d.citation;
        std::cout << "\n";
    }
}

void run(const TechniquesArgs& args) {
    const std::vector<catalog::Technique> all = catalog::techniques();
    std::vector<const catalog::Technique*> chosen;
    std::vector<std::string> names;
    for (const auto& t : all) {
        if (args.name.empty() || t.name == args.name) chosen.push_back(&t);
        names.push_back(t.kind + " " + t.name);
    }
    std::vector<std::string> plain;
    for (const std::string& n : names)
        plain.push_back(n.substr(n.find(' ') + 1));
    if (chosen.empty())
        usageError(fmt::format("unknown technique '{}'{} (known: {})", args.name,
                               didYouMean(args.name, plain), fmt::join(names, ", ")));

    // Availability needs a context; without one the list is still printed.
    std::optional<gpu::ContextInfo> info;
    std::string noContext;
    try {
        gpu::HeadlessContext context({args.device, false});
        info = context.info();
    } catch (const Error& e) {
        noContext = e.what();
    }
    if (args.json) {
        nlohmann::json out = nlohmann::json::array();
        for (const auto* t : chosen)
            out.push_back(catalog::techniqueJson(*t, info));
        std::cout << out.dump(2) << "\n";
        return;
    }
    std::cout << "GL driver: " << (info ? info->renderer : "none (" + noContext + ")") << "\n";
    for (const auto* t : chosen) {
        std::cout << "\n" << t->kind << " " << t->name << "  (available: ";
        if (t->cpu)
            std::cout << "yes, CPU; --integrator " << t->name;
        else
            std::cout << catalog::availability(*t, info);
        std::cout << ")\n  " << t->description << "\n";
        printProperties(*t->properties);
    }
    std::cout << "\nSet them in a scene as \"render\": {\"oit\": {\"type\": NAME, KEY: VALUE}} "
                 "(or \"shadows\": {...}) or with --set render.oit.KEY=VALUE "
                 "(render.shadows.KEY=VALUE); the path tracer's as \"render\": {\"pathtraced\": "
                 "{KEY: VALUE}} or --set render.pathtraced.KEY=VALUE.\n";
}

} // namespace

void addTechniquesCommand(CLI::App& app) {
    auto args = std::make_shared<TechniquesArgs>();
    CLI::App* cmd =
        app.add_subcommand("techniques", "List the registered techniques and their properties");
    cmd->add_option("name", args->name, "Only this technique");
    cmd->add_flag("--json", args->json, "Print JSON instead of text");
    cmd->add_option("--device", args->device, "EGL device index (availability check)")
        ->check(CLI::Range(-1, 64));
    cmd->callback([args] { run(*args); });
}

} // namespace veil::app
