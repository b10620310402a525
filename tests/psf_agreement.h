#pragma once
// How the fast glare paths' tests state their agreement with a float64 reference: the largest
// |test - reference| over the reference's peak, and the relative L2 error; and a PSF channel's
// root-mean-square radius.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "glare/wave/psf.h"

namespace glarelab::test {

struct Agreement {
  double max_over_peak = 0.0;  // max |test - reference| / max |reference|
  double relative_l2 = 0.0;
};

// Over `count` values from `test` and `reference`.
template <typename T>
Agreement compare_values(const T* test, const double* reference, std::size_t count) {
  double peak = 0.0, worst = 0.0, error = 0.0, norm = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const double d = static_cast<double>(test[k]) - reference[k];
    peak = std::max(peak, std::abs(reference[k]));
    worst = std::max(worst, std::abs(d));
    error += d * d;
    norm += reference[k] * reference[k];
  }
  return {worst / peak, std::sqrt(error / norm)};
}

template <typename T>
Agreement compare(const std::vector<T>& test, const std::vector<double>& reference) {
  return compare_values(test.data(), reference.data(), reference.size());
}

// One channel of two PSFs of the same size.
inline Agreement compare_channel(const Psf& test, const Psf& expected, int channel) {
  const std::size_t plane = static_cast<std::size_t>(expected.size_px) * expected.size_px;
  return compare_values(test.values.data() + channel * plane, expected.values.data() + channel * plane, plane);
}

// Root mean square distance (PSF pixels) of one channel from the centre pixel (N/2, N/2).
inline double rms_radius_px(const Psf& psf, int channel) {
  const int n = psf.size_px;
  double sum = 0.0, moment = 0.0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double w = psf.at(channel, x, y), dx = x - n / 2, dy = y - n / 2;
      sum += w;
      moment += w * (dx * dx + dy * dy);
    }
  return std::sqrt(moment / sum);
}

}  // namespace glarelab::test
