#pragma once
// One-dimensional value noise with three octaves (Ebert et al. 2003, "Texturing & Modeling",
// the noise Ritschel et al. 2009 use in Eq. 1 and for the accommodation microfluctuations).
// Lattice values are uniform in [-1, 1) from CounterRandom, so noise(x) is a pure function of
// (seed, channel, x): any time can be evaluated alone. Between lattice points the values are blended
// with the cubic smoothstep 3s^2 - 2s^3 (continuous first derivative). Octave o has lattice spacing
// 2^-o and weight 2^-o; the sum is divided by 1.75 so the result lies in [-1, 1].
#include <cstdint>

#include "glare/eye/eye_random_channels.h"
#include "core/random.h"

namespace glarelab {

class ValueNoise {
 public:
  ValueNoise(std::uint64_t seed, EyeChannel channel);

  // Three-octave noise in [-1, 1].
  double operator()(double x) const;
  // One octave (0, 1 or 2) at lattice frequency 2^octave, in [-1, 1].
  double octave(double x, int octave_index) const;
  // d/dx of operator(), for bounding frequency excursions of phase noise.
  double derivative(double x) const;

  // Standard deviation of operator() over x and seeds, exactly: one octave has variance
  // (1/3) * 26/35 (uniform lattice values, smoothstep blend), the three weighted octaves add
  // 1 + 1/4 + 1/16 of it, divided by 1.75^2.
  static double standard_deviation();
  // Largest |d/dx| operator() can reach: smoothstep slope 1.5 times a lattice difference of at most 2,
  // per octave times 2^o (frequency) times 2^-o (weight), over 1.75.
  static constexpr double kMaxDerivative = 3.0 * 3.0 / 1.75;

 private:
  double lattice(std::int64_t i, int octave_index) const;
  CounterRandom random_;
  EyeChannel channel_;
};

}  // namespace glarelab
