#pragma once
// A simulated participant of the straylight measurement (protocols/straylight_model.h) whose
// answers follow the physics of the display in front of it: the ring's light scattered by its own
// eye onto the test field, the display's own glow around the ring, and the compensation light.
#include <cstdint>
#include <memory>

#include "core/random.h"
#include "protocols/observer.h"
#include "protocols/straylight_model.h"

namespace glarelab {

struct StraylightObserverEye {
  // L_eq at the test field per cd/m2 of ring luminance: the eye's glare spread function integrated
  // over the ring (for a CIE 146 eye, glare/analytic/ring_straylight.h's cie146_ring_veil_fraction).
  double ring_veil_fraction = 0.0;
  // Its discrimination of the two flicker amplitudes and its lapses.
  StraylightPsychometric psychometric;
};

// What one trial shows, in cd/m2 at the eye: the ring's luminance when on, the display's own stray
// light on the test field while the ring is on, and the counterphase compensation light.
struct StraylightStimulus {
  double ring_luminance_cd_m2 = 0.0;
  double display_glow_cd_m2 = 0.0;
  double compensation_cd_m2 = 0.0;
};

class StraylightObserver {
 public:
  StraylightObserver(StraylightObserverEye eye, std::uint64_t seed)
      : eye_(eye), random_(seed, RandomStream::observer) {}

  // Whether the compensated half is answered as flickering more. Each half's flicker amplitude
  // (plain: veil + glow; compensated: |veil + glow - compensation|) is seen as its log10 plus
  // Gaussian noise of SD amplitude_noise_log10 / sqrt(2), so the difference has the model's SD;
  // with probability lapse the answer is a coin toss. Draws: (seed, observer stream, trial_index).
  bool compensated_stronger(const StraylightStimulus& stimulus, std::uint64_t trial_index) const;

  const StraylightObserverEye& eye() const { return eye_; }

 private:
  StraylightObserverEye eye_;
  CounterRandom random_;
};

// The simulated participant of a session (`--observer simulated` with [procedure] type =
// "straylight"): each plan's straylight stimulus (TrialPlan::straylight) answered by a
// StraylightObserver with `eye`, "left" or "right" naming the half it sees flicker more, after a
// lognormal response time of median `response_time_median_s`. std::invalid_argument for a plan
// without a straylight stimulus.
std::unique_ptr<Observer> make_straylight_participant(const StraylightObserverEye& eye, std::uint64_t seed,
                                                      double response_time_median_s);

}  // namespace glarelab
