#version 450 core
// Depth-only pass: no colour output; the rasterizer writes depth.
void main() {}
