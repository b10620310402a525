#pragma once
// Pupil and hippus (Ritschel et al. 2009, section 3.2).
//   Eq. 2 (Moon and Spencer 1944): p = 4.9 - 3 tanh(0.4 (log10 L + 1))  [mm, L field luminance cd/m2]
//   Eq. 1: h(t, p) = p + noise(t / p) * (p_max / p) * sqrt(1 - p / p_max)
// The field luminance is the time-damped mean luminance of the displayed frames (Ritschel 3.2 after
// Durand and Dorsey 2000): a first-order low-pass, solved exactly between frames.
#include <cstdint>
#include <vector>

#include "glare/eye/eye_parameters.h"
#include "glare/eye/value_noise.h"

namespace glarelab {

// Eq. 2, unclamped: 7.9 mm in the dark, 1.9 mm in very bright light. Requires L > 0.
double moon_spencer_pupil_diameter_mm(double field_luminance_cd_m2);

// The first-order adaptation of Luidolt 2020 section 5.1 (after Krawczyk et al. 2005), the one
// definition used by the field luminance below and by the perception stages (stimuli/perception/).
// Eq. 5.4: the rod sensitivity sigma(Y) = Y_half / (Y_half + Y), 1 in the dark, 1/2 at Y_half.
double rod_sensitivity(double luminance_cd_m2, double half_sensitivity_cd_m2);
// Eq. 5.3: tau(Y) = sigma(Y) tau_rod + (1 - sigma(Y)) tau_cone.
double adaptation_time_constant_s(double luminance_cd_m2, double tau_rod_s, double tau_cone_s,
                                  double half_sensitivity_cd_m2);
// Eq. 5.2 for a luminance Y held for elapsed_s: L = Y + (L_start - Y) exp(-elapsed_s / tau). This is
// the exact solution of dL/dt = (Y - L) / tau over the interval, so steps compose: two steps of
// dt / 2 give one step of dt (to rounding) and the result does not depend on the frame rate.
double adapted_luminance_after_cd_m2(double start_cd_m2, double luminance_cd_m2, double elapsed_s, double tau_s);

// Field luminance L(t) from the mean luminances Y_i of the frames shown at times t_i:
//   dL/dt = (Y(t) - L) / tau(Y(t)),  tau(Y) = sigma(Y) tau_rod + (1 - sigma(Y)) tau_cone,
//   sigma(Y) = Y_half / (Y_half + Y)                 (Luidolt 2020 Eqs. 5.3, 5.4)
// with Y(t) = Y_i from t_i until the next frame. Between frames the solution is exact,
//   L(t) = Y_i + (L(t_i) - Y_i) exp(-(t - t_i) / tau(Y_i))   (Luidolt Eq. 5.2 with ft = t - t_i),
// so the result does not depend on the frame rate. Before the first frame L = initial value.
class FieldLuminanceHistory {
 public:
  explicit FieldLuminanceHistory(const EyeParameters& parameters);

  // Frames must come in non-decreasing time; a mean luminance must be finite and >= 0.
  void record_frame(double time_s, double mean_luminance_cd_m2);
  double field_luminance_cd_m2(double time_s) const;
  double time_constant_s(double luminance_cd_m2) const;
  std::size_t frame_count() const { return frames_.size(); }

 private:
  struct Frame {
    double time_s;
    double mean_cd_m2;
    double field_at_start_cd_m2;  // L(t_i), integrated exactly from the frames before
  };
  double initial_cd_m2_;
  double tau_rod_s_, tau_cone_s_, half_sensitivity_cd_m2_;
  std::vector<Frame> frames_;
};

class PupilModel {
 public:
  PupilModel(const EyeParameters& parameters, std::uint64_t seed);

  // Eq. 2 for the mean diameter (field luminance floored at 1e-12 cd/m2, where Eq. 2 is within
  // 1e-3 mm of its 7.9 mm asymptote, so a black field is defined).
  double mean_diameter_mm(double field_luminance_cd_m2) const;
  // Eq. 1 around a mean diameter, clamped to [pupil_min_diameter_mm, pupil_max_diameter_mm].
  double hippus_diameter_mm(double time_s, double mean_diameter_mm) const;
  // The amplitude factor of Eq. 1, (p_max / p) sqrt(1 - p / p_max), times the noise scale.
  double hippus_amplitude_mm(double mean_diameter_mm) const;

 private:
  double max_mm_, min_mm_, noise_amplitude_;
  ValueNoise noise_;
};

}  // namespace glarelab
