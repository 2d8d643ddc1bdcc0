// The opaque objects (pass::ObjectSet::Opaque) into the frame's hdr and depth targets:
// forward Lambert + GGX with Schlick Fresnel, emission and the ambient term (times the AO
// buffer where an AO stage wrote ao.visibility), a receiver of the shadow technique. With AO
// on, the frame also has a depth pre-pass stage (`depth`): the same program with its colour
// masked and its shading skipped, so the shaded pass's GL_LEQUAL test passes exactly where
// the pre-pass wrote.
#pragma once

#include "gpu/objects.h"
#include "gpu/shader.h"
#include "pass/stage.h"

namespace veil::frame {

class OpaqueStage : public pass::Stage {
public:
    enum class Mode {
        DepthPrepass,      // `depth`: the depth alone
        Shaded,            // `opaque`, clearing depth
        ShadedAfterPrepass // `opaque` over the pre-pass's depth (GL_LEQUAL)
    };
    // `program`: shaders frame/mesh.vert + frame/opaque.frag (with VEIL_AO when the frame
    // has AO), shared by the pre-pass and the shaded pass.
    OpaqueStage(const gpu::ProgramManager& programs, gpu::ProgramHandle program, Mode mode)
        : programs_(programs), program_(program), mode_(mode) {}

    std::string name() const override { return mode_ == Mode::DepthPrepass ? "depth" : "opaque"; }
    std::vector<pass::Pass> passes(const pass::Assembly& assembly) override;
    void resize(pass::Context& context) override;

private:
    void draw(const pass::Context& context) const;

    const gpu::ProgramManager& programs_;
    gpu::ProgramHandle program_;
    Mode mode_;
    gpu::Framebuffer fbo_{gpu::NoCreate};
};

// tonemap (scope Pixels, compute): exposure, the operator (ACES fit [Narkowicz16] or clamp)
// and sRGB from hdr into the LDR target (frame resource ldr), over the context's region.
class TonemapStage : public pass::Stage {
public:
    explicit TonemapStage(gpu::ProgramManager& programs);
    std::string name() const override { return "tonemap"; }
    std::vector<pass::Pass> passes(const pass::Assembly& assembly) override;

private:
    const gpu::ProgramManager& programs_;
    gpu::ProgramHandle program_;
};

} // namespace veil::frame
