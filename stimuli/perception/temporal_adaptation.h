#pragma once
// Temporal adaptation of the eye (Luidolt 2020, section 5.1, after Krawczyk et al. 2005):
//   L_i = L_{i-1} + (Y - L_{i-1}) (1 - exp(-ft / tau(Y)))                  (Eq. 5.2)
//   tau(Y) = sigma(Y) tau_rod + (1 - sigma(Y)) tau_cone                    (Eq. 5.3)
//   sigma(Y) = 0.04 / (0.04 + Y)                                           (Eq. 5.4)
// with tau_rod = 0.4 s, tau_cone = 0.1 s, Y the frame's adaptation luminance
// (frame_adaptation_luminance.h) and ft the time the frame is shown. Eq. 5.2 is the exact solution
// of dL/dt = (Y - L) / tau(Y) for a luminance held for ft, so the adapted luminance after a stretch
// of constant input is the same at 60, 90 or 144 Hz, or for irregular frame times. The formulas are
// glare/eye/pupil_model.h's (the pupil's field luminance is the same filter), called, not repeated.
#include "core/perception_settings.h"

namespace glarelab {

// Throws std::invalid_argument naming the field when a constant is not finite and > 0.
void validate_adaptation_time_constants(const AdaptationTimeConstants& constants);

// The adapted luminance of one eye, a state advanced frame by frame.
class TemporalAdaptation {
 public:
  // The eye starts adapted to initial_adapted_cd_m2 (finite, >= 0).
  TemporalAdaptation(double initial_adapted_cd_m2, const AdaptationTimeConstants& constants = {});

  // Eq. 5.2 for a frame of adaptation luminance frame_luminance_cd_m2 shown for frame_time_s
  // (finite, >= 0); returns the new adapted luminance L_i in cd/m2.
  double advance(double frame_luminance_cd_m2, double frame_time_s);

  double adapted_luminance_cd_m2() const { return adapted_cd_m2_; }
  // Eq. 5.4 at the adapted luminance: 1 in full darkness (rods alone), 0 in bright light.
  double rod_sensitivity() const;
  const AdaptationTimeConstants& constants() const { return constants_; }

 private:
  AdaptationTimeConstants constants_;
  double adapted_cd_m2_;
};

}  // namespace glarelab
