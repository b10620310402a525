#pragma once
// IEEE 754 binary16 ("half") from float32, rounded to nearest even: the storage of frames that
// only reach the display encoder (runner/session/glared_region.h). Half keeps 11 significant bits,
// so a normal value is off by at most 2^-11 relative (4.9e-4); below 2^-14 (6.1e-5) the step is
// the fixed 2^-24 (6.0e-8) of the subnormals.
#include <cstdint>

namespace glarelab {

// Largest finite half, 65504. Magnitudes above it (and infinities) are clamped to it rather than
// made infinite: stored frames hold cd/m2, and no display's peak (PQ's 10,000 cd/m2) comes near,
// so the encoder clips them to the same code either way. NaN stays NaN.
inline constexpr float kLargestHalf = 65504.0f;

std::uint16_t half_from_float(float value);
float float_from_half(std::uint16_t bits);  // exact (every half is a float)

}  // namespace glarelab
