#pragma once
// IEEE 754 binary16 ("half") from float32, rounded to nearest even: the storage of frames that
// only reach the display encoder (runner/session/glared_region.h). Half keeps 11 significant bits,
// so a normal value is off by at most 2^-11 relative (4.9e-4); below 2^-14 (6.1e-5) the step is
// the fixed 2^-24 (6.0e-8) of the subnormals.
#include <bit>
#include <cmath>
#include <cstdint>

namespace glarelab {

// Largest finite half, 65504. Magnitudes above it (and infinities) are clamped to it rather than
// made infinite: stored frames hold cd/m2, and no display's peak (PQ's 10,000 cd/m2) comes near,
// so the encoder clips them to the same code either way. NaN stays NaN.
inline constexpr float kLargestHalf = 65504.0f;

// Inline: a stored frame converts every value of its changed rectangle, and a call per value
// kept the loop from being optimised as one (a sixteenth of a glare session's time).
inline std::uint16_t half_from_float(float value) {
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

float float_from_half(std::uint16_t bits);  // exact (every half is a float)

}  // namespace glarelab
