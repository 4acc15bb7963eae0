#version 460
// Splat pass, fragment stage of the paper's one pass: it writes depth where the disc is kept,
// so the test must come after the mask (early tests would write the discarded corners too).
#include "splat_fragment.glsl"
