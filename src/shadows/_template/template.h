// TEMPLATE for a new shadow technique: copy src/shadows/_template/ to src/shadows/<name>/ and
// shaders/shadows/_template/ to shaders/shadows/<name>/, rename, and add register<Name>() to
// TechniqueKind::registerBuiltins() in src/shadows/registry.cpp. docs/architecture.md ("Adding a
// shadow technique") says what a technique gets from the frame and must give.
//
// This template is a complete, working technique (`template`: the opaque casters' depth maps,
// as `opaque`, with one declared property) so that copying it gives something that renders.
// It is not registered by default (`veil techniques` does not list it):
// tests/gl/technique_template_test.cpp registers it with one line, renders it together with
// the OIT template (src/oit/_template) and checks the shadowed and lit floor against the
// analytic shading, so the template cannot rot.
//
// Parameter block (declared once in registerTemplate(); the scene, --set, the viewer, the
// report and `veil techniques` all read that declaration):
//   size       [2048]  [16, 16384]  texels per side of each light view's map
//   max_lights [4]     [1, 8]       most shadow-casting lights (more is an error)
//   bias       [0.01]  [0, 1e6]     opaque map depth bias, world units along the light axis
//   pcf_radius [1]     [0, 16]      opaque map PCF kernel, (2r+1)^2 taps
//   strength   [1]     [0, 1]       fraction of the light an opaque caster blocks: the
//                                   receivers get 1 - strength x (1 - V), V the filtered
//                                   depth-map visibility of [Williams78] (an example of a
//                                   property reaching the visibility include through
//                                   fillParams(): params[1].x).
#pragma once

#include "shadows/technique.h"

namespace veil::shadows {

void registerTemplate(Registry& registry);

} // namespace veil::shadows
