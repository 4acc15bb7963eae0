#pragma once
// IEEE 754 half precision, for packed GPU data (Gaussian records, float16 textures).
#include <cstdint>

namespace pbdsplat::core {

// Round to nearest even; overflow gives infinity, NaN stays NaN, subnormals are kept.
uint16_t float_to_half(float f);
float half_to_float(uint16_t h);

} // namespace pbdsplat::core
