#include "glare/analytic/cie_glare_spread.h"

#include <algorithm>

namespace glarelab {

double cie146_age_factor(double age_years) {
  const double a = age_years / 62.5;
  return 1.0 + (a * a) * (a * a);
}

double cie146_glare_spread_for_factor_per_sr(double angle_deg, double wide_angle_factor, double pigmentation) {
  const double t = angle_deg;
  return 10.0 / (t * t * t) + (5.0 / (t * t) + 0.1 * pigmentation / t) * wide_angle_factor + 0.0025 * pigmentation;
}

double cie146_glare_spread_per_sr(double angle_deg, double age_years, double pigmentation) {
  return cie146_glare_spread_for_factor_per_sr(angle_deg, cie146_age_factor(age_years), pigmentation);
}

double cie146_scattered_per_sr(double angle_deg, double age_years, double pigmentation) {
  return cie146_glare_spread_per_sr(std::max(angle_deg, kCieGlareMinAngleDeg), age_years, pigmentation);
}

}  // namespace glarelab
