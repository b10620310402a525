#pragma once
// Second moments of a PSF in visual angle, the observer frame (x to the observer's right, y up; the
// image's row 0 is at the top): what the refraction tests compare with the geometric blur ellipse.
// A uniform ellipse of semi-axes a >= b has <u^2> = a^2 / 4 along its major axis and b^2 / 4 across.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "glare/wave/psf.h"

namespace glarelab::test {

struct PsfMoments {
  double xx_deg2 = 0.0, xy_deg2 = 0.0, yy_deg2 = 0.0;
  double semi_major_deg = 0.0;  // 2 sqrt(largest eigenvalue): a uniform ellipse's semi-axis
  double semi_minor_deg = 0.0;
  double major_angle_deg = 0.0;  // [0, 180), counterclockwise from +x
  double energy = 0.0;
};

// Moments about the centroid of the pixels within window_deg of the grid centre.
inline PsfMoments psf_moments(const Psf& psf, int channel,
                              double window_deg = std::numeric_limits<double>::infinity()) {
  const int n = psf.size_px;
  const double dpp = psf.degrees_per_pixel;
  double sum = 0.0, mx = 0.0, my = 0.0;
  auto visit = [&](auto&& body) {
    for (int row = 0; row < n; ++row)
      for (int col = 0; col < n; ++col) {
        const double x = (col - n / 2) * dpp, y = (n / 2 - row) * dpp;
        if (std::hypot(x, y) > window_deg) continue;
        body(x, y, psf.at(channel, col, row));
      }
  };
  visit([&](double x, double y, double w) {
    sum += w;
    mx += w * x;
    my += w * y;
  });
  mx /= sum;
  my /= sum;
  PsfMoments m;
  m.energy = sum;
  visit([&](double x, double y, double w) {
    m.xx_deg2 += w * (x - mx) * (x - mx);
    m.xy_deg2 += w * (x - mx) * (y - my);
    m.yy_deg2 += w * (y - my) * (y - my);
  });
  m.xx_deg2 /= sum;
  m.xy_deg2 /= sum;
  m.yy_deg2 /= sum;
  const double half_difference = 0.5 * (m.xx_deg2 - m.yy_deg2);
  const double radius = std::hypot(half_difference, m.xy_deg2);
  const double mean = 0.5 * (m.xx_deg2 + m.yy_deg2);
  m.semi_major_deg = 2.0 * std::sqrt(mean + radius);
  m.semi_minor_deg = 2.0 * std::sqrt(std::max(0.0, mean - radius));
  double angle = 0.5 * std::atan2(m.xy_deg2, half_difference) * 180.0 / std::numbers::pi;
  if (angle < 0.0) angle += 180.0;
  m.major_angle_deg = angle;
  return m;
}

// Fraction of a channel's light within radius_deg of the grid centre.
inline double encircled_fraction(const Psf& psf, int channel, double radius_deg) {
  const int n = psf.size_px;
  double inside = 0.0, total = 0.0;
  for (int row = 0; row < n; ++row)
    for (int col = 0; col < n; ++col) {
      const double value = psf.at(channel, col, row);
      total += value;
      if (std::hypot(col - n / 2, n / 2 - row) * psf.degrees_per_pixel <= radius_deg) inside += value;
    }
  return inside / total;
}

// The smallest difference between two axis directions (degrees, modulo 180).
inline double axis_difference_deg(double a_deg, double b_deg) {
  const double d = std::fmod(std::abs(a_deg - b_deg), 180.0);
  return std::min(d, 180.0 - d);
}

}  // namespace glarelab::test
