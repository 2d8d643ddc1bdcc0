// What joins the OIT technique and the fog in the frame's `transparent` pass: the
// transparent-surface programs (one per geometry pass, with the technique's emit include) and
// the fog's contribution through the same oitEmit() (shaders/volume/fog_emit.*, or piecewise
// between the technique's stored surfaces: fog_segments.comp for a technique with
// fogSegments(), `reference`). The technique declares the pass (oit::Technique::passes); these
// are its hooks.
#pragma once

#include "gpu/shader.h"
#include "oit/technique.h"
#include "volume/fog_pass.h"

#include <string>
#include <vector>

namespace veil::frame {

struct TransparencyPrograms {
    std::vector<gpu::ProgramHandle> surface; // one per geometry pass
    std::vector<gpu::ProgramHandle> fogEmit; // one per geometry pass with fog (empty: none)
};

// Builds the programs of `technique` (and, with fog, its fog emission: compute where the
// technique's emit file writes its targets as images, oit::PerPixelEmit, else a full-screen
// fragment; or the piecewise march, FogPass::enableSegments). `visibility` is the shadow
// technique's "veil:light_visibility" include.
TransparencyPrograms buildTransparencyPrograms(const oit::Technique& technique,
                                               volume::FogPass* fog, gpu::ProgramManager& programs,
                                               const gpu::IncludeAliases& visibility);

// The hooks of the technique's transparent pass: its surface programs, the fog's emission
// before the surfaces of each geometry pass, the piecewise fog march after the surfaces of the
// last one. `reads`: what the pass reads besides depth.
oit::Technique::GeometryHooks transparencyHooks(const oit::Technique& technique,
                                                volume::FogPass* fog,
                                                const gpu::ProgramManager& programs,
                                                const TransparencyPrograms& built,
                                                std::vector<std::string> reads);

} // namespace veil::frame
