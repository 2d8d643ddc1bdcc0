// `moment-p4`, `moment-p6`, `moment-p8`, `moment-t3`, `moment-t4`: moment-based
// order-independent transparency [Munstermann18] with float32 storage and
// additive blending only; `moment-p4-16`, `moment-p6-16`, `moment-p8-16`, `moment-t3-16`,
// `moment-t4-16`: 16-bit quantized storage with a read-modify-write under
// GL_ARB_fragment_shader_interlock (unavailable without it); `moment-p4-half` ... `moment-t4-half`:
// unnormalized moments in half floats with additive blending only (any driver). See
// moment.cpp for the parameter block and shaders/oit/moment/emit.glsl for the storage layout.
#pragma once

#include "oit/cpu/moments.h"
#include "oit/technique.h"

#include <memory>
#include <string>

namespace veil::oit {

// Technique parameters (defaults: [Munstermann18] and docs/oit.md#moment-constants, see
// moment.cpp).
struct MomentTechniqueParams {
    cpu::MomentParams reconstruction; // overestimation, bias, bias vector, wrapping zone
    // Log-depth warp range [Munstermann18 sec. 3.3]. zMin <= 0 means the camera's near/far planes;
    // an application with a bounding sphere of its transparent geometry passes
    // cpu::depthRangeFromSphere(...) here.
    double zMin = 0.0, zMax = 0.0;
    // Half storage only: b_0 and the per-channel b_0 (target 0) in RGBA16F instead of RGBA32F
    // (8 instead of 16 bytes per pixel; [Munstermann18 sec. 4.1] stores b_0 in 16 bits too).
    bool b0Half = false;
};

// Variants in one table; `variant` is the name without "moment-" ("p4", ..., "t4", "p4-16", ...,
// "t4-16", "p4-half", ..., "t4-half"; the "-16" ones need GL_ARB_fragment_shader_interlock).
MomentTechniqueParams defaultMomentTechniqueParams(const std::string& variant);
std::unique_ptr<Technique> createMomentTechnique(gpu::ProgramManager& programs,
                                                 const std::string& variant,
                                                 const MomentTechniqueParams& params);

void registerMoment(Registry& registry);

} // namespace veil::oit
