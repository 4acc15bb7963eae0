#version 460
// Splat pass, fragment stage of the pipelines that test depth without writing it (the
// Gaussian's colour pass, additive blending): see shared/splat_fragment.glsl.

// Testing before the shader runs changes nothing here but the cost: fragments hidden behind
// the visibility pass's surface are never shaded (a discard cannot turn off early tests,
// because nothing is written).
layout(early_fragment_tests) in;

#include "splat_fragment.glsl"
