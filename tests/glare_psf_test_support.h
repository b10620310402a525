#pragma once
// Helpers shared by the glare PSF tests: azimuthal averages, bilinear lookups in angle, and a
// test PSF for convolutions.
#include <cmath>
#include <vector>

#include "glare/wave/psf.h"

namespace glarelab::test {

// Azimuthal average of one channel in bins of width 1 px around (N/2, N/2): bin k holds the pixels
// whose distance from the centre rounds to k.
inline std::vector<double> radial_profile(const Psf& psf, int channel = 0) {
  const int n = psf.size_px;
  std::vector<double> sum(static_cast<std::size_t>(n), 0.0), count(static_cast<std::size_t>(n), 0.0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const auto bin = static_cast<std::size_t>(std::lround(std::hypot(x - n / 2, y - n / 2)));
      if (bin >= sum.size()) continue;
      sum[bin] += psf.at(channel, x, y);
      count[bin] += 1.0;
    }
  for (std::size_t k = 0; k < sum.size(); ++k) sum[k] = count[k] > 0 ? sum[k] / count[k] : 0.0;
  return sum;
}

// Vertex of the parabola through (k-1, k, k+1): sub-pixel position of an extremum at bin k.
inline double parabolic_vertex(const std::vector<double>& f, std::size_t k) {
  const double a = f[k - 1], b = f[k], c = f[k + 1];
  return static_cast<double>(k) + 0.5 * (a - c) / (a - 2.0 * b + c);
}

// Bilinear lookup of channel c at fractional pixel (x, y); zero outside.
inline double bilinear(const Psf& psf, int channel, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  auto value = [&](int xi, int yi) {
    if (xi < 0 || yi < 0 || xi >= psf.size_px || yi >= psf.size_px) return 0.0;
    return psf.at(channel, xi, yi);
  };
  return (1 - fy) * ((1 - fx) * value(x0, y0) + fx * value(x0 + 1, y0)) +
         fy * ((1 - fx) * value(x0, y0 + 1) + fx * value(x0 + 1, y0 + 1));
}

inline double channel_sum(const Psf& psf, int channel) {
  double sum = 0.0;
  const std::size_t count = static_cast<std::size_t>(psf.size_px) * psf.size_px;
  for (std::size_t k = 0; k < count; ++k) sum += psf.values[static_cast<std::size_t>(channel) * count + k];
  return sum;
}

// An asymmetric 3-channel PSF of m x m pixels, each channel summing to 1 (a misplaced or mirrored
// kernel shows).
inline Psf lopsided_psf(int m) {
  Psf psf;
  psf.size_px = m;
  psf.channels = 3;
  psf.values.assign(3 * static_cast<std::size_t>(m) * m, 0.0);
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (int y = 0; y < m; ++y)
      for (int x = 0; x < m; ++x) {
        const double dx = x - m / 2 - 0.3 * (c + 1), dy = y - m / 2 + 0.2;
        const double value = 1.0 / (1.0 + dx * dx + 2.0 * dy * dy) + 0.01 * ((x * 7 + y * 3 + c) % 5);
        psf.at(c, x, y) = value;
        sum += value;
      }
    for (int y = 0; y < m; ++y)
      for (int x = 0; x < m; ++x) psf.at(c, x, y) /= sum;
  }
  return psf;
}

}  // namespace glarelab::test
