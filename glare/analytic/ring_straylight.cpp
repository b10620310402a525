#include "glare/analytic/ring_straylight.h"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include "glare/analytic/cie_glare_spread.h"

namespace glarelab {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

void check_angle(double angle_deg, const char* what) {
  if (!(angle_deg >= kCieGlareMinAngleDeg && angle_deg <= kCieGlareMaxAngleDeg)) {
    throw std::invalid_argument(std::string(what) + " " + std::to_string(angle_deg) +
                                " deg lies outside CIE 146's range of 0.1-100 degrees");
  }
}

}  // namespace

double cie146_straylight_log10(double angle_deg, double wide_angle_factor, double pigmentation) {
  check_angle(angle_deg, "straylight angle");
  return std::log10(angle_deg * angle_deg * cie146_glare_spread_for_factor_per_sr(angle_deg, wide_angle_factor, pigmentation));
}

double cie146_ring_veil_fraction(double inner_deg, double outer_deg, double wide_angle_factor, double pigmentation) {
  check_angle(inner_deg, "ring inner angle");
  check_angle(outer_deg, "ring outer angle");
  if (!(outer_deg > inner_deg)) throw std::invalid_argument("ring outer angle must exceed the inner angle");
  // In u = ln theta: dOmega = 2 pi (pi/180)^2 theta^2 du, so the integrand is 2 pi (pi/180)^2 s(theta),
  // smooth in u, which Simpson's rule integrates to far below a thousandth with 512 intervals.
  constexpr int kIntervals = 512;
  const double u0 = std::log(inner_deg);
  const double h = (std::log(outer_deg) - u0) / kIntervals;
  double sum = 0.0;
  for (int i = 0; i <= kIntervals; ++i) {
    const double theta_deg = std::exp(u0 + h * i);
    const double s =
        theta_deg * theta_deg * cie146_glare_spread_for_factor_per_sr(theta_deg, wide_angle_factor, pigmentation);
    const double weight = (i == 0 || i == kIntervals) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    sum += weight * s;
  }
  return 2.0 * std::numbers::pi * kRadPerDeg * kRadPerDeg * sum * h / 3.0;
}

double cie146_factor_for_straylight(double log_s, double angle_deg, double pigmentation) {
  check_angle(angle_deg, "straylight angle");
  // s / theta^2 = GSF is linear in F: GSF = GSF(F = 0) + F (5 / theta^2 + 0.1 p / theta).
  const double t = angle_deg;
  const double gsf_per_sr = std::pow(10.0, log_s) / (t * t);
  const double fixed_per_sr = cie146_glare_spread_for_factor_per_sr(t, 0.0, pigmentation);
  const double per_factor_per_sr = 5.0 / (t * t) + 0.1 * pigmentation / t;
  const double factor = (gsf_per_sr - fixed_per_sr) / per_factor_per_sr;
  if (!(factor > 0.0)) {
    std::ostringstream out;
    out << "straylight log(s) " << log_s << " at " << angle_deg << " deg is below CIE 146's age-independent terms ("
        << std::log10(t * t * fixed_per_sr) << ")";
    throw std::invalid_argument(out.str());
  }
  return factor;
}

}  // namespace glarelab
