// The `volume` technique's per caster and light decisions ([Eisemann06 sec. 3.2], classify.comp):
// culled, clamped or infinite, from the receivers' slice map and the occluders' far depth per
// grid column. volume.cpp builds the inputs; tests run it on inputs of their own.
#pragma once

#include "gpu/objects.h"
#include "gpu/shader.h"

namespace veil::shadows {

// Columns of a caster's footprint per reduce group of classify.comp (its kChunk).
inline constexpr int kClassifyChunk = 1024;

// Runs classify.comp's two dispatches for `entries` = casters x slots over a `grid` x `grid`
// grid: `program` is in use with its uniforms set (but `finish`) and its receiver, occluder,
// bounds and caster buffers bound; `footprints` (8 bytes per entry) is cleared and bound here.
void runClassify(const gpu::Program& program, const gpu::Buffer& footprints, int entries, int grid);

} // namespace veil::shadows
