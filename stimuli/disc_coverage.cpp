#include "stimuli/disc_coverage.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace glarelab {
namespace {

// Antiderivative of sqrt(r^2 - x^2) on [-r, r]: (x sqrt(r^2 - x^2) + r^2 asin(x / r)) / 2.
double half_chord_integral(double x, double r) {
  const double t = std::clamp(x / r, -1.0, 1.0);
  return 0.5 * (r * t * r * std::sqrt(std::max(0.0, 1.0 - t * t)) + r * r * std::asin(t));
}

}  // namespace

// With the disc centred at the origin, the rectangle's column at abscissa x holds the chord
// [-s(x), s(x)], s = sqrt(r^2 - x^2), clipped to [y0, y1]: its length is min(y1, s) - max(y0, -s)
// when positive. Between the abscissae where s crosses |y0| or |y1| (and +-r) each bound is either
// the constant or the chord, so the length integrates piece by piece with the antiderivative of s.
double disc_rectangle_overlap(double cx, double cy, double radius_px, double x0, double y0, double x1, double y1) {
  const double r = radius_px;
  if (!(r > 0.0) || !(x1 > x0) || !(y1 > y0)) return 0.0;
  x0 -= cx, x1 -= cx, y0 -= cy, y1 -= cy;
  const double a = std::max(x0, -r), b = std::min(x1, r);
  if (!(b > a)) return 0.0;
  // The piece boundaries in increasing order (insertion into a fixed array: at most 4 cuts).
  std::array<double, 6> edges{};
  std::size_t count = 0;
  const auto insert = [&](double value) {
    std::size_t i = count++;
    for (; i > 0 && edges[i - 1] > value; --i) edges[i] = edges[i - 1];
    edges[i] = value;
  };
  insert(a);
  insert(b);
  for (const double y : {y0, y1}) {
    if (std::abs(y) < r) {
      const double x = std::sqrt(r * r - y * y);
      for (const double c : {-x, x})
        if (c > a && c < b) insert(c);
    }
  }
  double area = 0.0;
  for (std::size_t i = 0; i + 1 < count; ++i) {
    const double u = edges[i], v = edges[i + 1];
    if (!(v > u)) continue;
    const double mid = 0.5 * (u + v);
    const double s = std::sqrt(std::max(0.0, r * r - mid * mid));
    const bool top_is_chord = s < y1, bottom_is_chord = -s > y0;
    const double top = top_is_chord ? s : y1, bottom = bottom_is_chord ? -s : y0;
    if (!(top > bottom)) continue;  // the chord misses the rectangle on this whole piece
    const double chord = half_chord_integral(v, r) - half_chord_integral(u, r);
    area += (top_is_chord ? chord : y1 * (v - u)) - (bottom_is_chord ? -chord : y0 * (v - u));
  }
  return area;
}

}  // namespace glarelab
