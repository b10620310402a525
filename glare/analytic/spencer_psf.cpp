#include "glare/analytic/spencer_psf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace glarelab {

SpencerRegime parse_spencer_regime(const std::string& name) {
  if (name == "photopic") return SpencerRegime::photopic;
  if (name == "mesopic") return SpencerRegime::mesopic;
  if (name == "scotopic") return SpencerRegime::scotopic;
  if (name == "adaptive") return SpencerRegime::adaptive;
  throw std::invalid_argument("unknown regime '" + name + "' (photopic, mesopic, scotopic or adaptive)");
}

std::string to_string(SpencerRegime regime) {
  switch (regime) {
    case SpencerRegime::photopic: return "photopic";
    case SpencerRegime::mesopic: return "mesopic";
    case SpencerRegime::scotopic: return "scotopic";
    case SpencerRegime::adaptive: return "adaptive";
  }
  return "adaptive";
}

namespace spencer {

double f0_per_sr(double angle_deg) {
  const double x = angle_deg / 0.02;
  return 2.61e6 * std::exp(-x * x);
}

double f1_per_sr(double angle_deg) {
  const double a = angle_deg + 0.02;
  return 20.91 / (a * a * a);
}

double f2_per_sr(double angle_deg) {
  const double a = angle_deg + 0.02;
  return 72.37 / (a * a);
}

double halo_peak_deg(double wavelength_nm) { return 3.0 * wavelength_nm / kHaloReferenceWavelengthNm; }

double f3_per_sr(double angle_deg, double wavelength_nm) {
  const double d = angle_deg - halo_peak_deg(wavelength_nm);
  return 436.9 * (kHaloReferenceWavelengthNm / wavelength_nm) * std::exp(-19.75 * d * d);
}

Mixture with_age(const Mixture& mixture, double age_years) {
  const double a2 = age_years * age_years;
  const double shift = std::min(6.9e-9 * a2 * a2, mixture.f0);
  Mixture aged = mixture;
  aged.f0 -= shift;
  aged.f2 += shift;
  return aged;
}

namespace {

double smoothstep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

Mixture blend(const Mixture& a, const Mixture& b, double t) {
  return {a.f0 + t * (b.f0 - a.f0), a.f1 + t * (b.f1 - a.f1), a.f2 + t * (b.f2 - a.f2), a.f3 + t * (b.f3 - a.f3)};
}

}  // namespace

Mixture regime_mixture(SpencerRegime regime, double adaptation_cd_m2) {
  switch (regime) {
    case SpencerRegime::photopic: return kPhotopic;
    case SpencerRegime::mesopic: return kMesopic;
    case SpencerRegime::scotopic: return kScotopic;
    case SpencerRegime::adaptive: break;
  }
  const double log_l = std::log10(std::max(adaptation_cd_m2, 1e-12));
  const double lower = std::log10(kScotopicBelowCdM2), upper = std::log10(kPhotopicAboveCdM2);
  const double h = kRegimeBlendHalfWidthDecades;
  if (log_l < lower + h) return blend(kScotopic, kMesopic, smoothstep(lower - h, lower + h, log_l));
  return blend(kMesopic, kPhotopic, smoothstep(upper - h, upper + h, log_l));
}

double mixture_per_sr(const Mixture& mixture, double angle_deg, double wavelength_nm) {
  double p = mixture.f0 * f0_per_sr(angle_deg) + mixture.f1 * f1_per_sr(angle_deg) + mixture.f2 * f2_per_sr(angle_deg);
  if (mixture.f3 != 0.0) p += mixture.f3 * f3_per_sr(angle_deg, wavelength_nm);
  return p;
}

}  // namespace spencer
}  // namespace glarelab
