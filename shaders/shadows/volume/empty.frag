#version 450 core
// Depth pre-pass and shadow-volume faces: depth and stencil only, no colour.
void main() {}
