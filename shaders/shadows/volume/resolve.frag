#version 450 core
// One light's screen-space visibility from its stencil count ([Eisemann06 sec. 3.2], depth-fail):
// drawn with the stencil test "count == 0", over a layer cleared to 0, so it writes 1 where
// the receiver is outside every shadow volume.
layout(location = 0) out float outVisibility;
void main() { outVisibility = 1.0; }
