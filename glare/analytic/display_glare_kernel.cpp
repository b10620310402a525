#include "glare/analytic/display_glare_kernel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/parallel_for.h"

namespace glarelab {

double DisplayKernel::energy(int channel) const {
  const std::size_t n = static_cast<std::size_t>(width_px()) * height_px();
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += values[static_cast<std::size_t>(channel) * n + i];
  return sum;
}

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// The PSF density per unit display area at the point `at_mm` of the display plane (the line of
// sight meets the plane at the origin): P(theta) dOmega/dA, dOmega/dA = (n . v) / |v|^3 for the
// ray v from the eye to the point and the display normal n.
struct PlaneDensity {
  const AnalyticPsf& psf;
  int channel;
  double distance_mm;

  double operator()(glm::dvec2 at_mm) const {
    const glm::dvec3 ray(at_mm.x, at_mm.y, distance_mm);
    const glm::dvec3 normal(0.0, 0.0, 1.0);
    const double length = glm::length(ray);
    const double angle_deg = std::atan2(glm::length(at_mm), distance_mm) * kDegPerRad;
    return psf.per_sr(angle_deg, channel) * glm::dot(normal, ray) / (length * length * length);
  }
};

// Gauss-Legendre of order n on [a, b], for the orders the rules below use.
template <typename F>
double gauss(int n, F&& f, double a, double b) {
  using boost::math::quadrature::gauss;
  switch (n) {
    case 2: return gauss<double, 2>::integrate(f, a, b);
    case 3: return gauss<double, 3>::integrate(f, a, b);
    case 4: return gauss<double, 4>::integrate(f, a, b);
    case 6: return gauss<double, 6>::integrate(f, a, b);
    case 10: return gauss<double, 10>::integrate(f, a, b);
    default: return gauss<double, 20>::integrate(f, a, b);
  }
}

// Where the ray from the origin in direction `dir` enters and leaves the box [lo, hi]; enter is 0
// when the box holds the origin.
void ray_box(glm::dvec2 dir, glm::dvec2 lo, glm::dvec2 hi, double& enter, double& leave) {
  enter = 0.0;
  leave = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 2; ++axis) {
    if (std::abs(dir[axis]) < 1e-300) continue;  // parallel: the box holds the ray's line on this axis
    double t0 = lo[axis] / dir[axis], t1 = hi[axis] / dir[axis];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  }
}

// The radii (mm) where the profile changes scale: integration in radius splits there.
std::vector<double> radial_breaks_mm(const AnalyticPsf& psf, double distance_mm) {
  std::vector<double> breaks;
  for (double angle : {0.01, 0.02, 0.04, 0.07, 0.15, 0.3, 0.6}) breaks.push_back(distance_mm * std::tan(angle / kDegPerRad));
  for (double angle : psf.kink_angles_deg()) breaks.push_back(distance_mm * std::tan(angle / kDegPerRad));
  std::sort(breaks.begin(), breaks.end());
  return breaks;
}

// The pixel's energy in polar coordinates about the source: angle pieces between the corners'
// directions, radius pieces between the profile's breaks.
double polar_pixel_energy(const PlaneDensity& density, glm::dvec2 lo, glm::dvec2 hi, const std::vector<double>& breaks) {
  const bool holds_origin = lo.x <= 0.0 && hi.x >= 0.0 && lo.y <= 0.0 && hi.y >= 0.0;
  const glm::dvec2 centre = 0.5 * (lo + hi);
  const double centre_angle = std::atan2(centre.y, centre.x);
  std::vector<double> cuts;
  const glm::dvec2 corners[4] = {{lo.x, lo.y}, {hi.x, lo.y}, {hi.x, hi.y}, {lo.x, hi.y}};
  if (holds_origin) {
    cuts.push_back(0.0);
    for (const glm::dvec2& c : corners) {
      double a = std::atan2(c.y, c.x);
      if (a < 0.0) a += 2.0 * std::numbers::pi;
      cuts.push_back(a);
    }
    cuts.push_back(2.0 * std::numbers::pi);
  } else {
    for (const glm::dvec2& c : corners) cuts.push_back(std::remainder(std::atan2(c.y, c.x) - centre_angle, 2.0 * std::numbers::pi) + centre_angle);
  }
  std::sort(cuts.begin(), cuts.end());
  double sum = 0.0;
  for (std::size_t piece = 0; piece + 1 < cuts.size(); ++piece) {
    if (cuts[piece + 1] - cuts[piece] < 1e-15) continue;
    auto over_radius = [&](double angle) {
      const glm::dvec2 dir(std::cos(angle), std::sin(angle));
      double enter = 0.0, leave = 0.0;
      ray_box(dir, lo, hi, enter, leave);
      if (!(leave > enter)) return 0.0;
      double inner = 0.0, from = enter;
      auto radial = [&](double r) { return density(r * dir) * r; };
      for (double b : breaks) {
        if (b <= from || b >= leave) continue;
        inner += gauss(10, radial, from, b);
        from = b;
      }
      return inner + gauss(10, radial, from, leave);
    };
    sum += gauss(20, over_radius, cuts[piece], cuts[piece + 1]);
  }
  return sum;
}

// Tensor Gauss-Legendre over the pixel, m x m sub-squares of order n each.
double tensor_pixel_energy(const PlaneDensity& density, glm::dvec2 lo, glm::dvec2 hi, int n, int m) {
  double sum = 0.0;
  const glm::dvec2 step = (hi - lo) / static_cast<double>(m);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const glm::dvec2 a = lo + step * glm::dvec2(i, j), b = a + step;
      sum += gauss(n, [&](double y) { return gauss(n, [&](double x) { return density({x, y}); }, a.x, b.x); }, a.y, b.y);
    }
  return sum;
}

// How a pixel dx, dy from the source is integrated: polar near the source and across kinks, else
// a tensor rule of an order that follows the profile's local scale (in pixels).
struct PixelRule {
  bool polar = false;
  int order = 2;
  int subdivisions = 1;
};

PixelRule rule_for(const AnalyticPsf& psf, int dx, int dy, const DisplayGeometry& geometry) {
  const double pitch = geometry.pixel_pitch_mm, d = geometry.viewing_distance_mm;
  const double deg_per_px = std::atan(pitch / d) * kDegPerRad;  // the largest: at the line of sight
  const double r_px = std::hypot(static_cast<double>(dx), static_cast<double>(dy));
  double polar_px = std::max(12.0, 0.1 / deg_per_px);
  for (double kink : psf.kink_angles_deg()) polar_px = std::max(polar_px, d * std::tan(kink / kDegPerRad) / pitch + 2.0);
  PixelRule rule;
  if (r_px < polar_px) {
    rule.polar = true;
    return rule;
  }
  const double angle_deg = std::atan2(r_px * pitch, d) * kDegPerRad;
  double scale_deg = angle_deg + 0.02;
  if (psf.chromatic() && angle_deg > 0.7 && angle_deg < 5.1) scale_deg = std::min(scale_deg, 0.225);
  const double scale_px = scale_deg / deg_per_px;
  if (scale_px >= 24.0) rule.order = 2;
  else if (scale_px >= 10.0) rule.order = 3;
  else if (scale_px >= 5.0) rule.order = 4;
  else {
    rule.order = 4;
    rule.subdivisions = static_cast<int>(std::ceil(5.0 / scale_px));
  }
  return rule;
}

}  // namespace

double pixel_energy(const AnalyticPsf& psf, int channel, int dx, int dy, const DisplayGeometry& geometry) {
  const PlaneDensity density{psf, channel, geometry.viewing_distance_mm};
  const double p = geometry.pixel_pitch_mm;
  const glm::dvec2 lo((dx - 0.5) * p, (dy - 0.5) * p), hi((dx + 0.5) * p, (dy + 0.5) * p);
  const PixelRule rule = rule_for(psf, dx, dy, geometry);
  if (rule.polar) return polar_pixel_energy(density, lo, hi, radial_breaks_mm(psf, geometry.viewing_distance_mm));
  return tensor_pixel_energy(density, lo, hi, rule.order, rule.subdivisions);
}

DisplayKernel analytic_display_kernel(const AnalyticPsf& psf, const DisplayGeometry& geometry, int half_width_px,
                                      int half_height_px, int threads) {
  DisplayKernel kernel;
  kernel.half_width_px = half_width_px;
  kernel.half_height_px = half_height_px;
  kernel.channels = psf.chromatic() ? 3 : 1;
  kernel.values.assign(static_cast<std::size_t>(kernel.channels) * kernel.width_px() * kernel.height_px(), 0.0);
  // The PSF is radial and the pixels square: compute the quadrant dx, dy >= 0 and mirror it.
  parallel_chunks(half_height_px + 1, threads, [&](int first, int last) {
    for (int dy = first; dy < last; ++dy)
      for (int dx = 0; dx <= half_width_px; ++dx)
        for (int c = 0; c < kernel.channels; ++c) {
          const double e = pixel_energy(psf, c, dx, dy, geometry);
          kernel.at(c, dx, dy) = e;
          kernel.at(c, -dx, dy) = e;
          kernel.at(c, dx, -dy) = e;
          kernel.at(c, -dx, -dy) = e;
        }
  });
  for (int c = 0; c < kernel.channels; ++c) kernel.at(c, 0, 0) += psf.peak_fraction();
  return kernel;
}

double energy_within_rectangle(const AnalyticPsf& psf, int channel, const DisplayGeometry& geometry,
                               double half_width_mm, double half_height_mm) {
  using boost::math::quadrature::gauss_kronrod;
  const double d = geometry.viewing_distance_mm;
  auto to_edge_deg = [&](double phi) {
    const double c = std::cos(phi), s = std::sin(phi);
    const double rho = std::min(c > 1e-300 ? half_width_mm / c : 1e300, s > 1e-300 ? half_height_mm / s : 1e300);
    return std::atan2(rho, d) * kDegPerRad;
  };
  std::vector<double> breaks{0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 10.0, 30.0};
  for (double k : psf.kink_angles_deg()) breaks.push_back(k);
  std::sort(breaks.begin(), breaks.end());
  auto radial = [&](double to_deg) {
    double sum = 0.0, from = 0.0;
    auto f = [&](double t) { return psf.per_sr(t, channel) * std::sin(t / kDegPerRad); };
    for (double b : breaks) {
      if (b >= to_deg) break;
      sum += gauss_kronrod<double, 31>::integrate(f, from, b, 10, 1e-12);
      from = b;
    }
    sum += gauss_kronrod<double, 31>::integrate(f, from, to_deg, 10, 1e-12);
    return sum / kDegPerRad;  // dtheta in radians
  };
  const double corner = std::atan2(half_height_mm, half_width_mm);
  auto over_phi = [&](double phi) { return radial(to_edge_deg(phi)); };
  const double quarter = gauss_kronrod<double, 31>::integrate(over_phi, 0.0, corner, 10, 1e-11) +
                         gauss_kronrod<double, 31>::integrate(over_phi, corner, std::numbers::pi / 2.0, 10, 1e-11);
  return 4.0 * quarter + psf.peak_fraction();
}

}  // namespace glarelab
