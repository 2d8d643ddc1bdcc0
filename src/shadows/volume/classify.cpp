#include "shadows/volume/classify.h"

#include "shaders/common/bindings.h"

#include <cstdint>

namespace veil::shadows {

void runClassify(const gpu::Program& program, const gpu::Buffer& footprints, int entries,
                 int grid) {
    if (entries <= 0) return;
    // Reduce: a group per (caster x slot, chunk of footprint columns), enough chunks for a
    // footprint of the whole grid (the groups past a smaller footprint leave at once); then
    // finish: an invocation per (caster, slot).
    const std::uint32_t zero = 0;
    glClearNamedBufferData(footprints.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    footprints.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_FOOTPRINTS);
    const int chunks = (grid * grid + kClassifyChunk - 1) / kClassifyChunk;
    program.set("finish", 0);
    glDispatchCompute(static_cast<GLuint>(entries), static_cast<GLuint>(chunks), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    program.set("finish", 1);
    glDispatchCompute(static_cast<GLuint>((entries + 63) / 64), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

} // namespace veil::shadows
