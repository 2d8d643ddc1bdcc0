// Techniques of one kind by name (nvpro's renderer registry), with the properties
// each declares (properties.h). `Info` has at least `std::string name` and
// `PropertySchema properties`. TechniqueRegistry below is the registry of a kind of GPU
// technique, instantiated for OIT (src/oit/technique.h) and shadows (src/shadows/technique.h).
//
// Built-in techniques are added explicitly by each registry's instance() (static
// initialisers in static libraries are dropped by the linker).
#pragma once

#include "base/error.h"
#include "base/properties.h"
#include "base/suggest.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <memory>
#include <string>
#include <vector>

namespace veil {

template <class Info>
class NamedRegistry {
public:
    // `kind` names the technique kind in messages ("OIT technique", "shadow technique").
    explicit NamedRegistry(std::string kind) : kind_(std::move(kind)) {}

    void add(Info info) {
        VEIL_CHECK(!find(info.name), "{} '{}' registered twice", kind_, info.name);
        items_.push_back(std::move(info));
    }
    const Info* find(const std::string& name) const {
        for (const auto& t : items_)
            if (t.name == name) return &t;
        return nullptr;
    }
    const std::vector<Info>& all() const { return items_; }
    std::vector<std::string> names() const {
        std::vector<std::string> n;
        for (const auto& t : items_)
            n.push_back(t.name);
        return n;
    }
    const std::string& kind() const { return kind_; }
    // Throws veil::Error naming the nearest known name (a typo) and listing them all.
    const Info& get(const std::string& name, const std::string& where = {}) const {
        const Info* info = find(name);
        VEIL_CHECK(info, "{}unknown {} '{}'{} (known: {})", where.empty() ? "" : where + ": ",
                   kind_, name, didYouMean(name, names()), fmt::join(names(), ", "));
        return *info;
    }
    // Validates `values` (a JSON object of the technique's properties; "type" is ignored;
    // null = defaults); `where` is the JSON path for messages ("scene.json: /render/oit").
    Properties resolve(const std::string& name, const nlohmann::json& values,
                       const std::string& where) const {
        return get(name, where.empty() ? where : where + "/type")
            .properties.resolve(values, where, fmt::format("{} '{}'", kind_, name));
    }

protected:
    // The technique `name` made from `values` (validated as in resolve()) by its factory
    // `info.create(programs, properties)`, after `info.isAvailable(context)` (null = always);
    // the technique keeps its effective properties (`properties_`: Technique classes befriend
    // NamedRegistry). Throws veil::Error naming the technique and `context.renderer`.
    template <class Context, class Programs>
    auto createTechnique(const std::string& name, const Context& context, Programs& programs,
                         const nlohmann::json& values, const std::string& where) const {
        const Info& info = get(name, where.empty() ? where : where + "/type");
        Properties properties = resolve(name, values, where);
        VEIL_CHECK(!info.isAvailable || info.isAvailable(context),
                   "{} '{}' is not available on this GL driver ({})", kind_, name,
                   context.renderer);
        auto technique = info.create(programs, properties);
        technique->properties_ = std::move(properties);
        return technique;
    }

private:
    std::string kind_;
    std::vector<Info> items_;
};

// The one registry of a kind of GPU technique. `Kind` declares:
//   Info, Technique      the registry's entries and what their factories make;
//   Context, Programs    the driver description and program cache create() takes;
//   kName, kWhere        the kind in messages ("OIT technique") and the default JSON path of
//                        its properties ("render.oit");
//   kErrorsNameWhere     whether an error a technique's factory raises without naming `where`
//                        is prefixed with it (its own checks of its properties know no file);
//   registerBuiltins(registry)   adds the built-in techniques, once, on first use.
template <class Kind>
class TechniqueRegistry : public NamedRegistry<typename Kind::Info> {
public:
    TechniqueRegistry() : NamedRegistry<typename Kind::Info>(Kind::kName) {}

    static TechniqueRegistry& instance() {
        static TechniqueRegistry* registry = [] {
            auto* r = new TechniqueRegistry();
            Kind::registerBuiltins(*r);
            return r;
        }();
        return *registry;
    }

    // Throws veil::Error listing the known names, saying why it is unavailable here, or naming
    // a bad property (see resolve()).
    std::unique_ptr<typename Kind::Technique>
    create(const std::string& name, const typename Kind::Context& context,
           typename Kind::Programs& programs, const nlohmann::json& values = {},
           const std::string& where = Kind::kWhere) const {
        if constexpr (!Kind::kErrorsNameWhere) {
            return this->createTechnique(name, context, programs, values, where);
        } else {
            try {
                return this->createTechnique(name, context, programs, values, where);
            } catch (const Error& e) {
                const std::string what = e.what();
                if (where.empty() || what.find(where) != std::string::npos) throw;
                throw Error(fmt::format("{}: {}", where, what));
            }
        }
    }
};

} // namespace veil
