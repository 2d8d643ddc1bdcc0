// `transmittance-slicemap`: transmittance shadow maps from slice maps ([Eisemann06 sec. 3],
// Eisemann & Decoret 2006). For every light view (src/shadows/views.h) the semi-transparent
// casters are voxelized into light-space slice maps ([Eisemann06 sec. 2]), one per material
// class: the technique asks the frame for them (lightSliceMap()) and the frame's voxelize pass
// (voxelize::LightSliceMap) writes them into the resource shadow.slices. A receiver at slice s
// gets prod_c T_c^(n_c) with n_c the set slices of class c in front of it (bitCount over masked
// words), times the opaque casters' Williams map (DepthMaps). docs/shadows.md
// "transmittance-slicemap" has the design, the class mapping and what differs from [Eisemann06].
//
// Properties (declared once in registerTransmittanceSlicemap): size (1024 here; columns of
// every view's slice map = texels of its opaque map), max_lights, bias, pcf_radius, slices,
// local_slicing, method, classes.
#pragma once

#include "scene/scene.h"
#include "shadows/technique.h"

#include <glm/glm.hpp>

#include <vector>

namespace veil::shadows {

void registerTransmittanceSlicemap(Registry& registry);

namespace slicemap {

// The transmittance per crossing surface of a material ([McGuire16 Eq. 2]: 1 - alpha + alpha T),
// the quantity its class groups (shaders/frame/material.glsl surfaceTransmittance).
glm::dvec3 surfaceTransmittance(const scene::Material& m);

// Groups transmittances into at most `maxClasses` classes: distinct values (to 1e-4) each
// get their own class while there are few enough; beyond that, the two classes nearest in
// absorbance (-log T, weighted by member count) are merged repeatedly, and a class's
// transmittance is the geometric mean of its members (exact for the members it merges when
// they are equal). `assignment` (optional) receives each input's class.
std::vector<glm::dvec3> groupClasses(const std::vector<glm::dvec3>& transmittances, int maxClasses,
                                     std::vector<int>* assignment = nullptr);

// The transmittances of the scene's semi-transparent shadow casters (objects with "shadows"
// whose material is transparent), one per such object.
std::vector<glm::dvec3> casterTransmittances(const scene::Scene& scene);

} // namespace slicemap

} // namespace veil::shadows
