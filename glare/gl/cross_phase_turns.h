#pragma once
// The astigmatic cross term of the pupil phase on the GL aperture grid, prepared for the exact
// integer reduction of glare/shaders/psf_load_aperture_astigmatic.comp. On the grid of
// glare/eye/aperture_raster.h, pixel (i, j) sits at x = (i - N/2) dx, y = (N/2 - j) dx, so
//   2 pi E_xy x y / lambda = 2 pi b k,   b = E_xy dx^2 / lambda (turns),   k = (i - N/2)(N/2 - j),
// k an exact integer. Only frac(b) matters (k is an integer); it is handed to the shader as a
// 64-bit fixed-point fraction, frac(b) 2^64 rounded, so that |k| frac(b) modulo 1 is formed in
// wrapping integer arithmetic, without the rounding a float product b k would have (b k reaches
// hundreds of turns for a few dioptres of oblique astigmatism over a 9 mm pupil).
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

namespace glarelab::gl {

// b = E_xy dx^2 / lambda in turns per unit of k, in double.
double cross_phase_turns_per_index(double xy_dioptres, double pixel_mm, double wavelength_nm);

// frac(turns) 2^64, rounded to the nearest integer (modulo 2^64: a fraction that rounds up to a
// whole turn is 0), split into the high and low 32-bit words the shader takes as a uvec2.
struct FixedPointTurns {
  std::uint32_t high = 0;  // bits 63..32
  std::uint32_t low = 0;   // bits 31..0
};
FixedPointTurns fixed_point_fraction(double turns);

// exp(2 pi i m / 4096), m = 0..4095, computed in double and rounded to float: the shader's table.
inline constexpr int kCrossTableSize = 4096;
std::vector<glm::vec2> cross_phase_table();

}  // namespace glarelab::gl
