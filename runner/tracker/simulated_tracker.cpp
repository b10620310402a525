#include "runner/tracker/simulated_tracker.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/clock.h"

namespace glarelab {

namespace {
constexpr double kMaxPupilMm = 9.0;  // p_max of Ritschel 2009, Eq. 1
constexpr double kSaccadeDuration_s = 0.03;
// Sub-indices of CounterRandom(seed, tracker_simulation): one per independent use. 1 and 2 drew
// the blink schedule before the blinks came from the eyelid model; they stay unused.
constexpr std::uint32_t kSubFixation = 3, kSubFixationX = 4, kSubFixationY = 5, kSubMeasurement = 6;
}  // namespace

namespace {
// The glare engine's pupil model with this tracker's hippus scale, so the simulated tracker reports
// the pupil of the same eye model (Ritschel et al. 2009, Eqs. 1 and 2).
EyeParameters tracker_eye_parameters(const SimulatedTrackerSettings& settings) {
  EyeParameters parameters;
  parameters.hippus_noise_amplitude = settings.hippus_noise_amplitude;
  return parameters;
}
}  // namespace

SimulatedTracker::SimulatedTracker(std::uint64_t seed, SimulatedTrackerSettings settings)
    : random_(seed, RandomStream::tracker_simulation),
      settings_(settings),
      pupil_(tracker_eye_parameters(settings), seed),
      eyelids_(EyeParameters{}, seed) {}

void SimulatedTracker::start(const SessionClock& clock) {
  // A resumed session continues its time line; the simulated eye starts where the clock is.
  start_s_ = clock.now_s();
  next_k_ = static_cast<std::int64_t>(std::ceil(start_s_ * settings_.rate_hz - 1e-9));
}

std::string SimulatedTracker::description() const {
  std::ostringstream text;
  text << "simulated (seed " << random_.seed() << ", " << settings_.rate_hz << " Hz per eye, hippus around "
       << pupil_.mean_diameter_mm(settings_.field_luminance_cd_m2) << " mm)";
  return text.str();
}

void SimulatedTracker::extend_schedules(double t_s) const {
  while (fixation_start_s_.empty() || fixation_start_s_.back() <= t_s) {
    const auto n = static_cast<std::uint64_t>(fixation_start_s_.size());
    const double previous = fixation_start_s_.empty() ? 0.0 : fixation_start_s_.back();
    const double duration = settings_.mean_fixation_s * (0.45 + 1.1 * random_.uniform(n, kSubFixation));
    fixation_start_s_.push_back(n == 0 ? 0.0 : previous + duration);
    fixation_x_.push_back(0.1 + 0.8 * random_.uniform(n, kSubFixationX));
    fixation_y_.push_back(0.1 + 0.8 * random_.uniform(n, kSubFixationY));
  }
}

bool SimulatedTracker::blinking(double t_s) const { return eyelids_.blink_closure(t_s) > 0.0; }

TrackerSample SimulatedTracker::sample(std::int64_t k, int eye) const {
  const double t = static_cast<double>(k) / settings_.rate_hz;
  TrackerSample out;
  out.eye = eye;
  out.device_time_s = t;
  out.session_time_s = t;
  if (blinking(t)) {
    // What a real tracker reports while the lid covers the pupil (Luidolt 2020, 7.2).
    out.pupil_diameter_mm = 0.0;
    out.confidence = 0.0;
    out.valid = false;
    return out;
  }
  const double hippus_mm = pupil_.hippus_diameter_mm(t, pupil_.mean_diameter_mm(settings_.field_luminance_cd_m2));
  const auto index = static_cast<std::uint64_t>(k);
  out.pupil_diameter_mm =
      hippus_mm + settings_.measurement_noise_mm * random_.normal(index, kSubMeasurement + static_cast<std::uint32_t>(eye));
  out.confidence = 0.95;
  out.valid = true;
  // Gaze: fixations joined by 30 ms linear saccades.
  extend_schedules(t);
  const auto it = std::upper_bound(fixation_start_s_.begin(), fixation_start_s_.end(), t);
  const auto i = static_cast<std::size_t>(it - fixation_start_s_.begin()) - 1;
  double x = fixation_x_[i];
  double y = fixation_y_[i];
  const double since = t - fixation_start_s_[i];
  if (i > 0 && since < kSaccadeDuration_s) {
    const double w = since / kSaccadeDuration_s;
    x = fixation_x_[i - 1] + (x - fixation_x_[i - 1]) * w;
    y = fixation_y_[i - 1] + (y - fixation_y_[i - 1]) * w;
  }
  out.gaze_x = x;
  out.gaze_y = y;
  return out;
}

TrackerBatch SimulatedTracker::poll(double now_s) {
  TrackerBatch batch;
  while (static_cast<double>(next_k_) / settings_.rate_hz <= now_s) {
    for (int eye = 0; eye < 2; ++eye) batch.samples.push_back(sample(next_k_, eye));
    ++next_k_;
  }
  status_.samples += static_cast<std::int64_t>(batch.samples.size());
  return batch;
}

}  // namespace glarelab
