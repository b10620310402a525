#include "glare/eye/pupil_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace glarelab {

double moon_spencer_pupil_diameter_mm(double field_luminance_cd_m2) {
  // Ritschel Eq. 2 (Moon and Spencer 1944; Spencer et al. 1995 write the logarithm as log10).
  return 4.9 - 3.0 * std::tanh(0.4 * (std::log10(field_luminance_cd_m2) + 1.0));
}

double rod_sensitivity(double luminance_cd_m2, double half_sensitivity_cd_m2) {
  return half_sensitivity_cd_m2 / (half_sensitivity_cd_m2 + luminance_cd_m2);  // Luidolt Eq. 5.4
}

double adaptation_time_constant_s(double luminance_cd_m2, double tau_rod_s, double tau_cone_s,
                                  double half_sensitivity_cd_m2) {
  const double sigma = rod_sensitivity(luminance_cd_m2, half_sensitivity_cd_m2);
  return sigma * tau_rod_s + (1.0 - sigma) * tau_cone_s;  // Luidolt Eq. 5.3
}

double adapted_luminance_after_cd_m2(double start_cd_m2, double luminance_cd_m2, double elapsed_s, double tau_s) {
  // Luidolt Eq. 5.2, L_i = L_{i-1} + (Y - L_{i-1}) (1 - exp(-ft / tau)), written around Y.
  return luminance_cd_m2 + (start_cd_m2 - luminance_cd_m2) * std::exp(-elapsed_s / tau_s);
}

FieldLuminanceHistory::FieldLuminanceHistory(const EyeParameters& parameters)
    : initial_cd_m2_(parameters.initial_field_luminance_cd_m2),
      tau_rod_s_(parameters.field_luminance_rod_time_constant_s),
      tau_cone_s_(parameters.field_luminance_cone_time_constant_s),
      half_sensitivity_cd_m2_(parameters.field_luminance_rod_half_sensitivity_cd_m2) {}

double FieldLuminanceHistory::time_constant_s(double luminance_cd_m2) const {
  return adaptation_time_constant_s(luminance_cd_m2, tau_rod_s_, tau_cone_s_, half_sensitivity_cd_m2_);
}

void FieldLuminanceHistory::record_frame(double time_s, double mean_luminance_cd_m2) {
  if (!std::isfinite(time_s) || !std::isfinite(mean_luminance_cd_m2) || mean_luminance_cd_m2 < 0.0)
    throw std::invalid_argument("eye model: frame mean luminance must be finite and >= 0 (got " +
                                std::to_string(mean_luminance_cd_m2) + " cd/m2 at " + std::to_string(time_s) + " s)");
  if (!frames_.empty() && time_s < frames_.back().time_s)
    throw std::invalid_argument("eye model: frames must be recorded in time order (" + std::to_string(time_s) +
                                " s after " + std::to_string(frames_.back().time_s) + " s)");
  const double start = field_luminance_cd_m2(time_s);
  frames_.push_back(Frame{time_s, mean_luminance_cd_m2, start});
}

double FieldLuminanceHistory::field_luminance_cd_m2(double time_s) const {
  // The last frame shown at or before time_s.
  const auto after = std::upper_bound(frames_.begin(), frames_.end(), time_s,
                                      [](double t, const Frame& frame) { return t < frame.time_s; });
  if (after == frames_.begin()) return initial_cd_m2_;
  const Frame& frame = *(after - 1);
  return adapted_luminance_after_cd_m2(frame.field_at_start_cd_m2, frame.mean_cd_m2, time_s - frame.time_s,
                                       time_constant_s(frame.mean_cd_m2));
}

PupilModel::PupilModel(const EyeParameters& parameters, std::uint64_t seed)
    : max_mm_(parameters.pupil_max_diameter_mm),
      min_mm_(parameters.pupil_min_diameter_mm),
      noise_amplitude_(parameters.hippus_noise_amplitude),
      noise_(seed, EyeChannel::hippus) {}

double PupilModel::mean_diameter_mm(double field_luminance_cd_m2) const {
  return moon_spencer_pupil_diameter_mm(std::max(field_luminance_cd_m2, 1e-12));
}

double PupilModel::hippus_amplitude_mm(double mean_diameter_mm) const {
  const double p = mean_diameter_mm;
  return noise_amplitude_ * (max_mm_ / p) * std::sqrt(std::max(0.0, 1.0 - p / max_mm_));
}

double PupilModel::hippus_diameter_mm(double time_s, double mean_diameter_mm) const {
  // Eq. 1: the noise runs at t / p, so small (bright-adapted) pupils oscillate faster and, through
  // the amplitude factor, more strongly (Ritschel Fig. 3). t in s and p in mm, as in the paper.
  const double p = mean_diameter_mm;
  const double h = p + noise_(time_s / p) * hippus_amplitude_mm(p);
  return std::clamp(h, min_mm_, max_mm_);
}

}  // namespace glarelab
