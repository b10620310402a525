#include "glare/analytic/analytic_psf.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "glare/wave/cie_cmf.h"
#include "glare/analytic/cie_glare_spread.h"
#include "glare/analytic/ring_straylight.h"

namespace glarelab {

GlareModel parse_glare_model(const std::string& name) {
  if (name == "ritschel") return GlareModel::ritschel;
  if (name == "spencer") return GlareModel::spencer;
  if (name == "cie") return GlareModel::cie;
  if (name == "hybrid") return GlareModel::hybrid;
  if (name == "luidolt") return GlareModel::luidolt;
  if (name == "human") return GlareModel::human;
  throw std::invalid_argument("unknown glare model '" + name + "' (human, ritschel, spencer, cie, hybrid or luidolt)");
}

std::string to_string(GlareModel model) {
  switch (model) {
    case GlareModel::ritschel: return "ritschel";
    case GlareModel::spencer: return "spencer";
    case GlareModel::cie: return "cie";
    case GlareModel::hybrid: return "hybrid";
    case GlareModel::luidolt: return "luidolt";
    case GlareModel::human: return "human";
  }
  return "ritschel";
}

void check_observer_eye(const ObserverEye& eye) {
  if (!(eye.age_years >= 1.0 && eye.age_years <= 100.0)) {
    std::ostringstream out;
    out << "age " << eye.age_years << " years is outside 1-100 years";
    throw std::invalid_argument(out.str());
  }
  if (!(eye.pigmentation >= 0.0 && eye.pigmentation <= 1.0)) {
    std::ostringstream out;
    out << "pigmentation " << eye.pigmentation << " is outside 0-1 (0 very dark eyes, 0.5 brown, 1 blue-green)";
    throw std::invalid_argument(out.str());
  }
  if (eye.straylight_log_s) {
    // cie146_factor_for_straylight refuses values no CIE eye has; the scattered light must leave a
    // non-negative peak (unit energy).
    const double scattered = 1.0 - AnalyticPsf::cie(eye).peak_fraction();
    if (!(scattered < 1.0)) {
      std::ostringstream out;
      out << "straylight log(s) " << *eye.straylight_log_s << " scatters " << scattered
          << " of the light (CIE 146 with more than all of it)";
      throw std::invalid_argument(out.str());
    }
  }
}

namespace {

constexpr int kHaloWavelengths = 50;
constexpr double kHaloFirstNm = 400.0, kHaloLastNm = 700.0;
constexpr double kHaloTableStepDeg = 0.001;
// The halo Gaussian exp(-19.75 d^2) is below 1e-15 of its peak beyond |d| = 1.33 degrees.
constexpr double kHaloReachDeg = 1.33;

}  // namespace

HaloSpectrum spencer_halo_spectrum() {
  HaloSpectrum spectrum;
  std::array<double, 3> sums{0.0, 0.0, 0.0};
  for (int i = 0; i < kHaloWavelengths; ++i) {
    const double nm = kHaloFirstNm + (kHaloLastNm - kHaloFirstNm) * i / (kHaloWavelengths - 1);
    const LinearRgb rgb = xyz_to_linear_rec709(cie1931_cmf(nm));
    const std::array<double, 3> w{std::max(rgb.r, 0.0), std::max(rgb.g, 0.0), std::max(rgb.b, 0.0)};
    spectrum.wavelengths_nm.push_back(nm);
    for (int c = 0; c < 3; ++c) {
      spectrum.channel_weights[c].push_back(w[c]);
      sums[c] += w[c];
    }
  }
  for (int c = 0; c < 3; ++c)
    for (double& w : spectrum.channel_weights[c]) w /= sums[c];
  return spectrum;
}

AnalyticPsf AnalyticPsf::spencer(const spencer::Mixture& mixture) {
  AnalyticPsf psf;
  psf.model_ = GlareModel::spencer;
  psf.mixture_ = mixture;
  if (mixture.f3 > 0.0) {
    const HaloSpectrum spectrum = spencer_halo_spectrum();
    psf.halo_table_start_deg_ = spencer::halo_peak_deg(kHaloFirstNm) - kHaloReachDeg;
    const double end_deg = spencer::halo_peak_deg(kHaloLastNm) + kHaloReachDeg;
    const int n = static_cast<int>(std::ceil((end_deg - psf.halo_table_start_deg_) / kHaloTableStepDeg)) + 4;
    for (int c = 0; c < 3; ++c) {
      psf.halo_table_[c].assign(static_cast<std::size_t>(n), 0.0);
      for (int k = 0; k < n; ++k) {
        const double angle = psf.halo_table_start_deg_ + k * kHaloTableStepDeg;
        double sum = 0.0;
        for (std::size_t i = 0; i < spectrum.wavelengths_nm.size(); ++i)
          sum += spectrum.channel_weights[c][i] * spencer::f3_per_sr(angle, spectrum.wavelengths_nm[i]);
        psf.halo_table_[c][static_cast<std::size_t>(k)] = sum;
      }
    }
  }
  return psf;
}

AnalyticPsf AnalyticPsf::spencer(SpencerRegime regime, double adaptation_cd_m2, const ObserverEye& eye) {
  AnalyticPsf psf = spencer(spencer::with_age(spencer::regime_mixture(regime, adaptation_cd_m2), eye.age_years));
  psf.eye_ = eye;
  return psf;
}

AnalyticPsf AnalyticPsf::cie(const ObserverEye& eye) {
  AnalyticPsf psf;
  psf.model_ = GlareModel::cie;
  psf.eye_ = eye;
  psf.cie_wide_angle_factor_ =
      eye.straylight_log_s
          ? cie146_factor_for_straylight(*eye.straylight_log_s, kStraylightReferenceAngleDeg, eye.pigmentation)
          : cie146_age_factor(eye.age_years);
  const double scattered = radial_energy([&](double t) { return psf.per_sr(t, 0); }, 0.0, 90.0, {kCieGlareMinAngleDeg});
  psf.peak_fraction_ = 1.0 - scattered;
  return psf;
}

double AnalyticPsf::halo_per_sr(double angle_deg, int channel) const {
  const std::vector<double>& table = halo_table_[channel];
  const double x = (angle_deg - halo_table_start_deg_) / kHaloTableStepDeg;
  if (x < 1.0 || x > static_cast<double>(table.size()) - 3.0) return 0.0;
  const int k = static_cast<int>(x);
  const double t = x - k;
  // 4-point Lagrange through k-1, k, k+1, k+2.
  const double lm1 = -t * (t - 1.0) * (t - 2.0) / 6.0, l0 = (t + 1.0) * (t - 1.0) * (t - 2.0) / 2.0;
  const double l1 = -(t + 1.0) * t * (t - 2.0) / 2.0, l2 = (t + 1.0) * t * (t - 1.0) / 6.0;
  return lm1 * table[k - 1] + l0 * table[k] + l1 * table[k + 1] + l2 * table[k + 2];
}

double AnalyticPsf::cie_scattered_per_sr(double angle_deg) const {
  // The formula with its core held at 0.1 degrees (glare/analytic/cie_glare_spread.h).
  return cie146_glare_spread_for_factor_per_sr(std::max(angle_deg, kCieGlareMinAngleDeg), cie_wide_angle_factor_,
                                               eye_.pigmentation);
}

double AnalyticPsf::per_sr(double angle_deg, int channel) const {
  if (model_ == GlareModel::cie) return cie_scattered_per_sr(angle_deg);
  double p = mixture_.f0 * spencer::f0_per_sr(angle_deg) + mixture_.f1 * spencer::f1_per_sr(angle_deg) +
             mixture_.f2 * spencer::f2_per_sr(angle_deg);
  if (mixture_.f3 > 0.0) p += mixture_.f3 * halo_per_sr(angle_deg, channel);
  return p;
}

double AnalyticPsf::per_sr_at_wavelength(double angle_deg, double wavelength_nm) const {
  if (model_ == GlareModel::cie) return cie_scattered_per_sr(angle_deg);
  return spencer::mixture_per_sr(mixture_, angle_deg, wavelength_nm);
}

double AnalyticPsf::profile_per_sr(double angle_deg) const {
  if (model_ == GlareModel::cie)
    return cie146_glare_spread_for_factor_per_sr(angle_deg, cie_wide_angle_factor_, eye_.pigmentation);
  return spencer::mixture_per_sr(mixture_, angle_deg, spencer::kHaloReferenceWavelengthNm);
}

std::vector<double> AnalyticPsf::kink_angles_deg() const {
  if (model_ == GlareModel::cie) return {kCieGlareMinAngleDeg};
  return {};
}

double radial_energy(const std::function<double(double)>& per_sr, double from_deg, double to_deg,
                     const std::vector<double>& breaks_deg) {
  // Break points where the models change fastest, plus the caller's.
  std::vector<double> points{from_deg, to_deg};
  for (double b : {0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 10.0, 30.0})
    points.push_back(b);
  points.insert(points.end(), breaks_deg.begin(), breaks_deg.end());
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  const double to_rad = std::numbers::pi / 180.0;
  auto integrand = [&](double t) { return per_sr(t) * std::sin(t * to_rad); };
  double sum = 0.0;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const double a = points[i], b = points[i + 1];
    if (a < from_deg || b > to_deg || b <= a) continue;
    sum += boost::math::quadrature::gauss_kronrod<double, 61>::integrate(integrand, a, b, 15, 1e-12);
  }
  return std::numbers::pi * std::numbers::pi / 90.0 * sum;
}

}  // namespace glarelab
