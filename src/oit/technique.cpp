#include "oit/technique.h"

namespace veil::oit {

std::vector<pass::Pass> Technique::passes(GeometryHooks hooks) {
    // The technique's accumulation targets are frame resources of their own (debug views,
    // --dump); oit.accumulation stands for its storage as a whole (lists, buffers).
    std::vector<std::string> accumulation = {"oit.accumulation"}, resolved = {"hdr"};
    for (const Resource& r : resources())
        (r.writtenByResolve ? resolved : accumulation).push_back(r.name);
    std::vector<std::string> reads = {"depth"};
    reads.insert(reads.end(), hooks.reads.begin(), hooks.reads.end());

    pass::Pass transparent{"transparent", reads, accumulation, nullptr};
    transparent.scope = pass::Scope::Pixels;
    transparent.receivesShadows = true;
    transparent.execute = [this, hooks = std::move(hooks)](const pass::Context& context) {
        for (int pass = 0; pass < geometryPasses(); ++pass) {
            const gpu::Program& program = hooks.surfaceProgram(pass);
            program.set("useOverride", 0);
            if (context.prepareReceiver) context.prepareReceiver(program);
            beginAccumulate(pass, context, program);
            if (hooks.beforeSurfaces) hooks.beforeSurfaces(context, pass);
            context.drawObjects(program, pass::ObjectSet::Transparent);
            if (hooks.afterSurfaces) hooks.afterSurfaces(context, pass);
            endAccumulate(pass);
            if (pass + 1 == geometryPasses() && repeatAccumulation()) pass = -1;
        }
    };

    std::vector<std::string> resolveReads = accumulation;
    resolveReads.push_back("hdr");
    pass::Pass resolvePass{"resolve", resolveReads, resolved,
                           [this](const pass::Context& context) { resolve(context); }};
    resolvePass.scope = pass::Scope::Pixels;
    return {std::move(transparent), std::move(resolvePass)};
}

} // namespace veil::oit
