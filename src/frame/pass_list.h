// The frame as an ordered list of passes (docs/architecture.md "One frame: passes and resources"):
// the modules' declared passes (pass::Pass, src/pass/pass.h) concatenated, each with a name (its
// GPU timer's name too), the named frame resources it reads and writes (`depth`, `hdr`,
// `shadow.<what>`, `fog.radiance`, `oit.accumulation`, `ldr`, ...), its scope and execute().
// The list is checked once when it is built: a pass that reads a resource no earlier pass
// writes is an error naming both, not a black image.
#pragma once

#include "pass/pass.h"

#include <string>
#include <vector>

namespace veil::frame {

using Pass = pass::Pass;

class PassList {
public:
    PassList& add(Pass pass);
    // Throws veil::Error when a pass reads a resource that no earlier pass writes, or when two
    // passes share a name. `external` lists resources that exist before the first pass.
    void validate(const std::vector<std::string>& external = {}) const;

    const std::vector<Pass>& passes() const { return passes_; }
    const Pass* find(const std::string& name) const;
    // Every resource some pass writes, in first-write order (debug views, reports).
    std::vector<std::string> resources() const;
    // "shadow: -> shadow.0 | opaque: shadow.0 -> depth, hdr | ..." for logs and reports.
    std::string describe() const;

private:
    std::vector<Pass> passes_;
};

} // namespace veil::frame
