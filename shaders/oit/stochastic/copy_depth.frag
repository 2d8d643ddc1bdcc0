#version 450 core
// Copies the single-sample opaque depth (pass::Context::depth) into every sample of the
// technique's multisampled depth buffer (depth func ALWAYS, writes on), so the stochastic
// passes z-test per sample against the opaque geometry [Enderton11 sec. 3.5 step 1]. Runs per pixel: the
// opaque depth is one value per pixel, and full coverage writes it to all samples.
#include "../../common/bindings.h"

layout(binding = VEIL_TEX_OIT0 + 3) uniform sampler2D opaqueDepth;

void main() { gl_FragDepth = texelFetch(opaqueDepth, ivec2(gl_FragCoord.xy), 0).r; }
