// float32 <-> binary16 by bit manipulation (IEEE 754-2008, 3.6: binary16 has 5 exponent bits with
// bias 15 and 10 fraction bits; float32 8 bits with bias 127 and 23 bits).
#include "core/half_float.h"

#include <bit>
#include <cmath>

namespace glarelab {

std::uint16_t half_from_float(float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  const auto sign = static_cast<std::uint16_t>((bits >> 16) & 0x8000u);
  const std::uint32_t magnitude = bits & 0x7fffffffu;
  if (magnitude > 0x7f800000u) return static_cast<std::uint16_t>(sign | 0x7e00u);  // NaN (quiet)
  // 65520 (0x477ff000) is halfway between 65504 and the next step (2^16): from there on round to
  // nearest even would give infinity; see kLargestHalf.
  if (magnitude >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7bffu);
  if (magnitude < 0x38800000u) {
    // Below the smallest normal half (2^-14): a subnormal, value / 2^-24 rounded to nearest even.
    // The scaling by 2^24 is exact; the result is at most 1024, the smallest normal's bits.
    const float units = std::bit_cast<float>(magnitude) * 16777216.0f;
    return static_cast<std::uint16_t>(sign | static_cast<std::uint16_t>(std::nearbyint(units)));
  }
  // Normal: rebias the exponent (127 -> 15) and drop 13 fraction bits, rounding to nearest even
  // (a carry out of the fraction correctly bumps the exponent).
  const std::uint32_t rebiased = magnitude - (static_cast<std::uint32_t>(127 - 15) << 23);
  const std::uint32_t rounded = rebiased + 0x0fffu + ((rebiased >> 13) & 1u);
  return static_cast<std::uint16_t>(sign | (rounded >> 13));
}

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
