#include "glare/analytic/cie_glare_spread.h"

#include <algorithm>

namespace glarelab {

double cie146_glare_spread_per_sr(double angle_deg, double age_years, double pigmentation) {
  const double t = angle_deg;
  const double a = age_years / 62.5;
  const double age_factor = 1.0 + (a * a) * (a * a);
  return 10.0 / (t * t * t) + (5.0 / (t * t) + 0.1 * pigmentation / t) * age_factor + 0.0025 * pigmentation;
}

double cie146_scattered_per_sr(double angle_deg, double age_years, double pigmentation) {
  return cie146_glare_spread_per_sr(std::max(angle_deg, kCieGlareMinAngleDeg), age_years, pigmentation);
}

}  // namespace glarelab
