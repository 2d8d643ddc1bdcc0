#include "frame/pass_list.h"

#include "base/error.h"

#include <algorithm>

namespace veil::frame {

namespace {
std::string joined(const std::vector<std::string>& v) {
    std::string out;
    for (const std::string& s : v)
        out += (out.empty() ? "" : ", ") + s;
    return out;
}
bool contains(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}
} // namespace

PassList& PassList::add(Pass pass) {
    passes_.push_back(std::move(pass));
    return *this;
}

const Pass* PassList::find(const std::string& name) const {
    for (const Pass& p : passes_)
        if (p.name == name) return &p;
    return nullptr;
}

void PassList::validate(const std::vector<std::string>& external) const {
    std::vector<std::string> written = external, names;
    for (const Pass& p : passes_) {
        VEIL_CHECK(!p.name.empty(), "frame: a pass without a name");
        VEIL_CHECK(!contains(names, p.name), "frame: two passes are named '{}'", p.name);
        names.push_back(p.name);
        for (const std::string& r : p.reads)
            VEIL_CHECK(contains(written, r),
                       "frame: pass '{}' reads '{}', which no earlier pass writes (written so "
                       "far: {})",
                       p.name, r, written.empty() ? std::string("nothing") : joined(written));
        for (const std::string& w : p.writes)
            if (!contains(written, w)) written.push_back(w);
    }
}

std::vector<std::string> PassList::resources() const {
    std::vector<std::string> out;
    for (const Pass& p : passes_)
        for (const std::string& w : p.writes)
            if (!contains(out, w)) out.push_back(w);
    return out;
}

std::string PassList::describe() const {
    std::string out;
    for (const Pass& p : passes_)
        out += (out.empty() ? "" : " | ") + p.name + ": " + joined(p.reads) + " -> " +
               joined(p.writes);
    return out;
}

} // namespace veil::frame
