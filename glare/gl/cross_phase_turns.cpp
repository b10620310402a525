#include "glare/gl/cross_phase_turns.h"

#include <cmath>
#include <complex>
#include <numbers>

namespace glarelab::gl {

double cross_phase_turns_per_index(double xy_dioptres, double pixel_mm, double wavelength_nm) {
  // Phase 2 pi E_xy x y / lambda (glare/refraction/astigmatic_phase.h's cross term) with x y = k dx^2: in turns
  // per unit k, E_xy dx^2 / lambda, with dx in m and lambda in m.
  const double dx_m = pixel_mm * 1e-3;
  return xy_dioptres * dx_m * dx_m / (wavelength_nm * 1e-9);
}

FixedPointTurns fixed_point_fraction(double turns) {
  // |turns| - floor(|turns|) is exact in double (the integer part of a double is removed without
  // rounding), and scaling by 2^32 is exact, so the only rounding is the last bit of the low word
  // (2^-65 turns). A negative b is the two's complement of |b|'s fraction, also exact.
  const double magnitude = std::abs(turns);
  const double scaled_high = std::ldexp(magnitude - std::floor(magnitude), 32);
  const double high = std::floor(scaled_high);
  const double low = std::nearbyint(std::ldexp(scaled_high - high, 32));
  // high < 2^32; a low word that rounded up to 2^32 carries into it, and a carry past bit 63 (a
  // whole turn) wraps to 0, modulo 2^64 as the shader's arithmetic is.
  std::uint64_t value = (static_cast<std::uint64_t>(high) << 32) + static_cast<std::uint64_t>(low);
  if (turns < 0.0) value = ~value + 1u;
  return {static_cast<std::uint32_t>(value >> 32), static_cast<std::uint32_t>(value & 0xffffffffu)};
}

std::vector<glm::vec2> cross_phase_table() {
  std::vector<glm::vec2> table(kCrossTableSize);
  for (int m = 0; m < kCrossTableSize; ++m) {
    const std::complex<double> value = std::polar(1.0, 2.0 * std::numbers::pi * m / kCrossTableSize);
    table[static_cast<std::size_t>(m)] = glm::vec2(static_cast<float>(value.real()), static_cast<float>(value.imag()));
  }
  return table;
}

}  // namespace glarelab::gl
