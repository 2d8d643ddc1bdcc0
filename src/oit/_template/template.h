// TEMPLATE for a new OIT technique: copy src/oit/_template/ to src/oit/<name>/ and
// shaders/oit/_template/ to shaders/oit/<name>/, rename, and add register<Name>() to
// TechniqueKind::registerBuiltins() in src/oit/registry.cpp. docs/architecture.md walks
// through it.
//
// This template is a complete, working technique (`template`: unsorted blending with dual-
// source modulation, like `blend`, plus one declared property) so that copying it gives
// something that renders. tests/gl/oit_template_test.cpp registers it and checks that it
// equals `blend` with opacity_scale 1, so the template cannot rot.
//
// Parameter block (declared once in registerTemplate(); the scene, --set, the viewer, the
// report and `veil techniques` all read that declaration):
//   opacity_scale [1]  [0, 1]  multiplies every fragment's coverage alpha (an example of a
//                              property reaching the shader through prepareProgram()).
#pragma once

#include "oit/technique.h"

namespace veil::oit {

void registerTemplate(Registry& registry);

} // namespace veil::oit
