// Blackbody colour: Planck's spectral radiance integrated against the CIE 1931 2-degree
// colour-matching functions [CIE15] to XYZ, then to linear sRGB (IEC 61966-2-1 primaries,
// D65 white). The emission of temperature grids is built on it (docs/volumes.md "Emission").
#pragma once

#include <glm/glm.hpp>

#include <vector>

namespace veil::volume {

// CIE 1931 XYZ of a blackbody at `kelvin`: X = int B(lambda, T) xbar(lambda) dlambda over
// 380..780 nm in 5 nm steps (the CIE table's own grid), with B in W m^-2 sr^-1 m^-1 and the
// result in kW m^-2 sr^-1 (so Y is the ybar-weighted radiance; x 683 lm/W x 1000 gives cd/m^2).
glm::dvec3 blackbodyXyz(double kelvin);

// Linear sRGB of the same radiance. Below about 1900 K the colour lies outside the sRGB gamut
// and its blue component is negative; it is kept so the chromaticity is exact (tone maps clamp).
glm::dvec3 blackbodyRgb(double kelvin);

// The table the GPU interpolates (shaders/volume/fog_medium.glsl): `size` entries at
// T_i = i x maxKelvin / (size - 1), each (linear sRGB / Y, ln Y) of blackbodyRgb(T_i), so that
// linear interpolation in T of the colour and of ln Y (smooth in T, unlike Y, which changes by
// orders of magnitude) gives blackbodyRgb within 0.1 % above 1000 K (at 2048 entries to
// 25000 K). ln Y is clamped to -80 (exp underflows to 0 in single precision); entry 0 (T = 0)
// takes entry 1's colour.
std::vector<glm::vec4> blackbodyTable(int size, double maxKelvin);

glm::dvec3 xyzToLinearSrgb(const glm::dvec3& xyz);
glm::dvec3 linearSrgbToXyz(const glm::dvec3& rgb);

} // namespace veil::volume
