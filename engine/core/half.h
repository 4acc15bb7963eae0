#pragma once
// IEEE 754 half precision, for packed GPU data (Gaussian records, float16 textures).
#include <cstdint>
#include <cstring>

namespace pbdsplat::core {

// Round to nearest even; overflow gives infinity, NaN stays NaN, subnormals are kept.
uint16_t float_to_half(float f);
// For hot loops over values already known finite and within +-65504: rounds to nearest (ties
// away from zero) and flushes what would be a subnormal half (below 2^-14) to zero. A few
// integer operations, inline.
inline uint16_t float_to_half_in_range(float f) {
    uint32_t x;
    std::memcpy(&x, &f, 4);
    const uint32_t sign = (x >> 16) & 0x8000u, magnitude = x & 0x7fffffffu;
    if (magnitude < 0x38800000u) return uint16_t(sign);
    // Rebias the exponent (127 -> 15) and round at the mantissa's 13th bit; a carry moves into
    // the exponent, as it should.
    return uint16_t(sign | ((magnitude - 0x38000000u + 0x1000u) >> 13));
}
float half_to_float(uint16_t h);

} // namespace pbdsplat::core
