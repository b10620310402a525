#include "glare/refraction/spectacle_surface.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace glarelab {
namespace {

// The smootherstep E(x) = 10 x^3 - 15 x^4 + 6 x^5 on [0, 1], its derivative, and its first and
// second integrals from 0 (so g(s) = a_full L^2 E2(s / L) has g'' = a), each continued past 1 with
// E = 1.
double smootherstep(double x) { return x <= 0.0 ? 0.0 : x >= 1.0 ? 1.0 : x * x * x * (10.0 + x * (-15.0 + 6.0 * x)); }
double smootherstep_slope(double x) { return x <= 0.0 || x >= 1.0 ? 0.0 : 30.0 * x * x * (1.0 - x) * (1.0 - x); }
double smootherstep_integral(double x) {  // E1(x) = 2.5 x^4 - 3 x^5 + x^6; E1(1) = 1/2
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 0.5 + (x - 1.0);
  return x * x * x * x * (2.5 + x * (-3.0 + x));
}
double smootherstep_double_integral(double x) {  // E2(x) = x^5 / 2 - x^6 / 2 + x^7 / 7; E2(1) = 1/7
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0 / 7.0 + 0.5 * (x - 1.0) + 0.5 * (x - 1.0) * (x - 1.0);
  return x * x * x * x * x * (0.5 + x * (-0.5 + x / 7.0));
}

}  // namespace

SagSample ToricSurface::sample(glm::dvec2 at_m) const {
  const glm::dvec2 local = at_m - centre_m;
  const glm::dvec2 across(-sweep_direction.y, sweep_direction.x);
  const double u = glm::dot(local, sweep_direction);
  const double v = glm::dot(local, across);
  SagSample out;
  const double ct = tube_curvature_per_m;
  const double root_v = 1.0 - ct * ct * v * v;
  if (!(root_v > 0.0)) return out;
  const double sqrt_v = std::sqrt(root_v);
  const double sag_v = ct * v * v / (1.0 + sqrt_v);
  const double slope_v = ct * v / sqrt_v;
  const double denominator = 1.0 - sweep_curvature_per_m * sag_v;
  if (!(std::abs(denominator) > 1e-12)) return out;
  const double cu = sweep_curvature_per_m / denominator;  // the section's curvature at this v
  const double root_u = 1.0 - cu * cu * u * u;
  if (!(root_u > 0.0)) return out;
  const double sqrt_u = std::sqrt(root_u);
  out.sag_m = sag_v + cu * u * u / (1.0 + sqrt_u);
  const double d_sag_du = cu * u / sqrt_u;
  // d(c u^2 / (1 + sqrt(1 - c^2 u^2)))/dc = u^2 / (s (1 + s)) and dc_u'/dv = c_u'^2 dS_v/dv.
  const double d_sag_dv = slope_v * (1.0 + cu * cu * u * u / (sqrt_u * (1.0 + sqrt_u)));
  out.gradient = d_sag_du * sweep_direction + d_sag_dv * across;
  out.valid = true;
  return out;
}

double ProgressiveAddition::add_curvature_per_m(double below_cross_m) const {
  return full_add_curvature_per_m * smootherstep(below_cross_m / corridor_length_m);
}

SagSample ProgressiveAddition::sample(glm::dvec2 at_m) const {
  SagSample out;
  out.valid = true;
  if (!active()) return out;
  const double x = at_m.x - fitting_cross_m.x;
  const double length = corridor_length_m;
  const double fraction = (fitting_cross_m.y - at_m.y) / length;  // s / L, s the distance below the cross
  const double a = full_add_curvature_per_m;
  out.sag_m = a * length * length * smootherstep_double_integral(fraction) + 0.5 * a * smootherstep(fraction) * x * x;
  // ds/dy = -1.
  out.gradient.x = a * smootherstep(fraction) * x;
  out.gradient.y = -a * length * smootherstep_integral(fraction) - 0.5 * a * smootherstep_slope(fraction) * x * x / length;
  return out;
}

}  // namespace glarelab
