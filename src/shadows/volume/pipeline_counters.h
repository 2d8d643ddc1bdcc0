// ARB_pipeline_statistics_query counters for the `volume` shadow technique's stats() (GL 4.6
// core; Mesa lists the extension): one query per counter around a part of the pass, waited for
// at end() and summed over the lights.
#pragma once

#include "gpu/objects.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace veil::shadows {

struct PipelineCounters {
    static constexpr GLenum kTargets[] = {
        GL_VERTEX_SHADER_INVOCATIONS_ARB, GL_CLIPPING_INPUT_PRIMITIVES_ARB,
        GL_CLIPPING_OUTPUT_PRIMITIVES_ARB, GL_FRAGMENT_SHADER_INVOCATIONS_ARB,
        GL_COMPUTE_SHADER_INVOCATIONS_ARB};
    static constexpr const char* kNames[] = {
        "vertex_shader_invocations", "clipping_input_primitives", "clipping_output_primitives",
        "fragment_shader_invocations", "compute_shader_invocations"};
    bool on = false;
    std::vector<gpu::Query> queries;
    std::uint64_t sums[5] = {};
    explicit PipelineCounters(bool enabled) : on(enabled) {
        if (on)
            for (GLenum t : kTargets)
                queries.emplace_back(t);
    }
    void begin() const {
        for (const gpu::Query& q : queries)
            glBeginQuery(q.target(), q.id());
    }
    void end() {
        for (std::size_t i = 0; i < queries.size(); ++i) {
            glEndQuery(queries[i].target());
            sums[i] += queries[i].result();
        }
    }
    nlohmann::json json() const {
        nlohmann::json j = nlohmann::json::object();
        for (std::size_t i = 0; i < queries.size(); ++i)
            j[kNames[i]] = sums[i];
        return j;
    }
};

} // namespace veil::shadows
