#include "protocols/straylight_observer.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace glarelab {

bool StraylightObserver::compensated_stronger(const StraylightStimulus& stimulus, std::uint64_t trial_index) const {
  if (random_.uniform(trial_index, 0) < eye_.psychometric.lapse) return random_.uniform(trial_index, 1) < 0.5;
  const double plain_cd_m2 = eye_.ring_veil_fraction * stimulus.ring_luminance_cd_m2 + stimulus.display_glow_cd_m2;
  const double compensated_cd_m2 = std::abs(plain_cd_m2 - stimulus.compensation_cd_m2);
  // A half that does not flicker at all is never the stronger one.
  if (!(compensated_cd_m2 > 0.0)) return false;
  const double sigma = eye_.psychometric.amplitude_noise_log10 / std::numbers::sqrt2;
  const double seen_plain = std::log10(plain_cd_m2) + sigma * random_.normal(trial_index, 2);
  const double seen_compensated = std::log10(compensated_cd_m2) + sigma * random_.normal(trial_index, 3);
  return seen_compensated > seen_plain;
}

}  // namespace glarelab
