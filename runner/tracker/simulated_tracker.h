#pragma once
// A simulated binocular tracker at 120 Hz per eye: pupil from the hippus model of Ritschel et al.
// 2009 (Eq. 1) around the Moon-Spencer mean pupil (Eq. 2), blinks reported as a real tracker does
// (confidence 0, diameter 0), saccades between fixations, and measurement noise. Every value is a
// pure function of (seed, time): poll(t) returns exactly the samples up to t, in order.
//
// One blink schedule: the blinks are the glare engine's eyelid model's (glare/eye/eyelids.h) with the
// same seed, so a session's simulated tracker blinks exactly when its dynamic eye's lids move (the
// tracker loses the pupil for the whole lid movement, blink closure > 0).
#include <cstdint>
#include <vector>

#include "glare/eye/eyelids.h"
#include "glare/eye/pupil_model.h"
#include "core/random.h"
#include "runner/tracker/tracker_source.h"

namespace glarelab {

struct SimulatedTrackerSettings {
  double rate_hz = 120.0;                    // per eye
  double field_luminance_cd_m2 = 50.0;       // adapting luminance for Eq. 2
  double hippus_noise_amplitude = 0.25;      // scale of noise() in Eq. 1 (unitless)
  double measurement_noise_mm = 0.02;        // tracker noise, standard deviation
  double mean_fixation_s = 0.45;             // fixations 0.2..0.7 s, then a 30 ms saccade
};


class SimulatedTracker final : public TrackerSource {
 public:
  SimulatedTracker(std::uint64_t seed, SimulatedTrackerSettings settings = {});
  void start(const SessionClock& clock) override;
  void stop() override {}
  TrackerBatch poll(double now_s) override;
  bool live() const override { return false; }
  TrackerStatus status() const override { return status_; }
  std::string description() const override;

  // Sample k of `eye` (time k / rate_hz on the session clock), and whether a blink covers time t.
  TrackerSample sample(std::int64_t k, int eye) const;
  bool blinking(double t_s) const;
  const EyelidModel& eyelids() const { return eyelids_; }

 private:
  void extend_schedules(double t_s) const;

  CounterRandom random_;
  SimulatedTrackerSettings settings_;
  PupilModel pupil_;
  EyelidModel eyelids_;
  double start_s_ = 0.0;
  std::int64_t next_k_ = 0;
  TrackerStatus status_;
  // Lazily extended schedule: fixation onsets with targets.
  mutable std::vector<double> fixation_start_s_, fixation_x_, fixation_y_;
};

}  // namespace glarelab
