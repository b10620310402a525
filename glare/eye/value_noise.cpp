#include "glare/eye/value_noise.h"

#include <cmath>

namespace glarelab {

ValueNoise::ValueNoise(std::uint64_t seed, EyeChannel channel)
    : random_(seed, RandomStream::eye_model), channel_(channel) {}

double ValueNoise::lattice(std::int64_t i, int octave_index) const {
  // Two's complement keeps negative lattice indices distinct from positive ones.
  const auto index = static_cast<std::uint64_t>(i);
  return 2.0 * random_.uniform(index, eye_sub_index(channel_, static_cast<std::uint32_t>(octave_index))) - 1.0;
}

double ValueNoise::octave(double x, int octave_index) const {
  const double scaled = std::ldexp(x, octave_index);
  const double floor_x = std::floor(scaled);
  const auto i = static_cast<std::int64_t>(floor_x);
  const double s = scaled - floor_x;
  const double blend = s * s * (3.0 - 2.0 * s);
  const double a = lattice(i, octave_index);
  const double b = lattice(i + 1, octave_index);
  return a + (b - a) * blend;
}

double ValueNoise::operator()(double x) const {
  return (octave(x, 0) + 0.5 * octave(x, 1) + 0.25 * octave(x, 2)) / 1.75;
}

double ValueNoise::derivative(double x) const {
  double sum = 0.0;
  for (int o = 0; o < 3; ++o) {
    const double scaled = std::ldexp(x, o);
    const double floor_x = std::floor(scaled);
    const auto i = static_cast<std::int64_t>(floor_x);
    const double s = scaled - floor_x;
    const double slope = 6.0 * s * (1.0 - s);  // d smoothstep / ds
    // Chain rule: d(scaled)/dx = 2^o, octave weight 2^-o: the factors cancel.
    sum += (lattice(i + 1, o) - lattice(i, o)) * slope;
  }
  return sum / 1.75;
}

double ValueNoise::standard_deviation() {
  const double octave_variance = (1.0 / 3.0) * (26.0 / 35.0);
  return std::sqrt(octave_variance * (1.0 + 0.25 + 0.0625)) / 1.75;
}

}  // namespace glarelab
