#version 460
// Occluder pass: the surface's distance along the view axis, where it is the nearest.
layout(location = 0) in float v_depth;
layout(location = 0) out float out_depth;

void main() { out_depth = v_depth; }
