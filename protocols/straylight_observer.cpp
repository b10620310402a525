#include "protocols/straylight_observer.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

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

namespace {

// The spread of ln(response time), as the other simulated observers' (protocols/simulated_observer.cpp).
constexpr double kResponseTimeSigma = 0.25;

class StraylightParticipant : public Observer {
 public:
  StraylightParticipant(const StraylightObserverEye& eye, std::uint64_t seed, double response_time_median_s)
      : observer_(eye, seed), time_random_(seed, RandomStream::response_time), median_s_(response_time_median_s) {}

  std::string description() const override { return "simulated"; }

  Response respond(const TrialPlan& plan) override {
    if (!plan.straylight || plan.trial_index < 0)
      throw std::invalid_argument("simulated straylight participant: trial " + std::to_string(plan.trial_index) +
                                  " shows no straylight stimulus");
    const StraylightStimulusPlan& shown = *plan.straylight;
    const auto index = static_cast<std::uint64_t>(plan.trial_index);
    const bool compensated = observer_.compensated_stronger(
        {shown.ring_luminance_cd_m2, shown.display_glow_cd_m2, shown.compensation_cd_m2}, index);
    Response response;
    response.value = compensated == shown.compensation_left ? "left" : "right";
    response.response_time_s = median_s_ * std::exp(kResponseTimeSigma * time_random_.normal(index));
    return response;
  }

 private:
  StraylightObserver observer_;
  CounterRandom time_random_;
  double median_s_;
};

}  // namespace

std::unique_ptr<Observer> make_straylight_participant(const StraylightObserverEye& eye, std::uint64_t seed,
                                                      double response_time_median_s) {
  return std::make_unique<StraylightParticipant>(eye, seed, response_time_median_s);
}

}  // namespace glarelab
