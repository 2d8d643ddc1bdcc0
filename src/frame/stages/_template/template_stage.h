// TEMPLATE for a new stage of the frame: copy src/frame/stages/_template/ to
// src/frame/stages/<name>_stage.* (and shaders/frame/_template/ to shaders/frame/<name>/),
// rename, and build it where the frame's stages are built (frame::buildStages, frame_setup.cpp)
// or insert it into a renderer (frame::Renderer::insertStage). frame::Renderer is not edited:
// it runs whatever passes its stages declare. docs/architecture.md walks through it.
//
// This template is a complete, working stage (`template`): one pass of scope Pixels after the
// transparency's resolve that scales the frame's HDR image by a declared property, over the
// pass's region (so the viewer's tiled refinement runs it per tile). It reads and writes `hdr`
// and publishes nothing new. tests/gl/stage_template_test.cpp inserts it before `tonemap` and
// checks the image against the frame without it, so the template cannot rot.
//
// Parameter block (declared once in schema(); scene values would read the same declaration):
//   gain [1]  [0, 16]  multiplies the HDR radiance of every pixel.
#pragma once

#include "base/properties.h"
#include "gpu/shader.h"
#include "pass/stage.h"

namespace veil::frame {

class TemplateStage : public pass::Stage {
public:
    static const PropertySchema& schema();
    // `properties`: validated against schema() (PropertySchema::resolve).
    TemplateStage(gpu::ProgramManager& programs, Properties properties);

    std::string name() const override { return "template"; }
    std::vector<pass::Pass> passes(const pass::Assembly& assembly) override;

private:
    const gpu::ProgramManager& programs_;
    Properties properties_;
    gpu::ProgramHandle program_;
};

} // namespace veil::frame
