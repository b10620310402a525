// float32 <-> binary16 by bit manipulation (IEEE 754-2008, 3.6: binary16 has 5 exponent bits with
// bias 15 and 10 fraction bits; float32 8 bits with bias 127 and 23 bits).
#include "core/half_float.h"

#include <bit>
#include <cmath>

namespace glarelab {

float float_from_half(std::uint16_t bits) {
  const std::uint32_t sign = static_cast<std::uint32_t>(bits & 0x8000u) << 16;
  const std::uint32_t exponent = (bits >> 10) & 0x1fu;
  const std::uint32_t fraction = bits & 0x3ffu;
  if (exponent == 0) {
    // Zero or subnormal: fraction x 2^-24, exact in float.
    const float magnitude = static_cast<float>(fraction) * 5.9604644775390625e-8f;
    return sign != 0 ? -magnitude : magnitude;
  }
  if (exponent == 0x1f) return std::bit_cast<float>(sign | 0x7f800000u | (fraction << 13));  // inf, NaN
  return std::bit_cast<float>(sign | ((exponent + 127 - 15) << 23) | (fraction << 13));
}

}  // namespace glarelab
