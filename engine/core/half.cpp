#include "core/half.h"

#include <cmath>
#include <cstring>

namespace pbdsplat::core {

uint16_t float_to_half(float f) {
    uint32_t x;
    std::memcpy(&x, &f, 4);
    const uint32_t sign = (x >> 16) & 0x8000u;
    const int32_t exp = int32_t((x >> 23) & 0xffu);
    uint32_t mant = x & 0x7fffffu;
    if (exp == 255) return uint16_t(sign | 0x7c00u | (mant ? 0x200u : 0u));  // inf / nan
    int32_t e = exp - 127 + 15;
    if (e >= 31) return uint16_t(sign | 0x7c00u);  // overflow to inf
    if (e <= 0) {                                   // subnormal or zero
        if (e < -10) return uint16_t(sign);
        mant |= 0x800000u;
        const uint32_t shift = uint32_t(14 - e);
        uint32_t h = mant >> shift;
        const uint32_t rem = mant & ((1u << shift) - 1u), half = 1u << (shift - 1u);
        if (rem > half || (rem == half && (h & 1u))) ++h;
        return uint16_t(sign | h);
    }
    uint32_t h = (uint32_t(e) << 10) | (mant >> 13);
    const uint32_t rem = mant & 0x1fffu;
    if (rem > 0x1000u || (rem == 0x1000u && (h & 1u))) ++h;  // round to nearest even (may carry into exp)
    return uint16_t(sign | h);
}

float half_to_float(uint16_t h) {
    const uint32_t sign = uint32_t(h & 0x8000u) << 16;
    const uint32_t exp = (h >> 10) & 0x1fu;
    const uint32_t mant = h & 0x3ffu;
    float out;
    if (exp == 0) {
        out = std::ldexp(float(mant), -24);
        return sign ? -out : out;
    }
    uint32_t x;
    if (exp == 31) x = sign | 0x7f800000u | (mant << 13);
    else x = sign | ((exp + 112u) << 23) | (mant << 13);
    std::memcpy(&out, &x, 4);
    return out;
}

} // namespace pbdsplat::core
