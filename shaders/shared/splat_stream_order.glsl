// Where a drawn splat's entries in the streams beside the records (anisotropic axes, binding 3;
// view-dependent colour, binding 4) are: the records may be drawn in another order than the
// streams were written (the GPU sort gathers only the records), so the draw looks each splat's
// entries up through this list of original indices (binding 5: the sort's, or the identity).
#ifndef PBDSPLAT_SPLAT_STREAM_ORDER_GLSL
#define PBDSPLAT_SPLAT_STREAM_ORDER_GLSL

layout(set = 0, binding = 5, std430) readonly buffer StreamOrder { uint stream_order[]; };

uint stream_entry(uint drawn) { return stream_order[drawn]; }

#endif
