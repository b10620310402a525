#pragma once
// The compensation-comparison measurement (docs/STRAYLIGHT.md) as a sequence of trials: each
// shows one compensation level (log10 s_c, range finding then fixed levels,
// protocols/straylight_model.h) on a side drawn from the seeded generator, and takes the answer
// which half flickers more. Its state is the answers so far, so a replay of the stored responses
// reaches the same levels and sides.
#include <cstdint>
#include <vector>

#include "protocols/procedure.h"
#include "protocols/straylight_config.h"
#include "protocols/straylight_model.h"

namespace glarelab {

// What one trial of the measurement shows.
struct StraylightLevel {
  double log_compensation = 0.0;  // log10 s_c, within the compensation range
  bool compensation_left = false;  // the half that gets the counterphase light
  double compensation_cd_m2 = 0.0;  // L_c = k s_c L_ring
};

class StraylightProcedure : public Procedure {
 public:
  StraylightProcedure(const StraylightSpec& spec, std::uint64_t seed);

  bool finished() const override { return static_cast<int>(answers_.size()) >= spec_.answers; }
  // positions and answers {"left", "right"}: the half that flickers more; intensity: log10 s_c;
  // condition_json: the level, the compensated side, L_c and the ring.
  TrialPlan next_trial() override;
  // "left"/"right" is an answer (compensated_stronger when it names the compensated half; no
  // answer is correct); "timeout" moves on to a fresh side without an answer; anything else
  // (e.g. "abort") changes nothing.
  TrialOutcome record_response(const TrialPlan& plan, const Response& response) override;
  int planned_trials() const override { return spec_.answers; }

  // The level of the next trial (a pure function of the answers so far, the trials run and the seed).
  StraylightLevel next_level() const;
  const std::vector<StraylightAnswer>& answers() const { return answers_; }
  // The display's glow in straylight units, glow / (k L_ring), subtracted from the estimate.
  double display_straylight() const;
  // The estimate of the eye's log10 s from the answers so far (std::invalid_argument for none).
  StraylightEstimate estimate() const;

 private:
  StraylightSpec spec_;
  std::uint64_t seed_;
  StraylightSchedule schedule_;
  StraylightPsychometric psychometric_;
  std::vector<StraylightAnswer> answers_;
  int trials_run_ = 0;  // answers and timeouts: the counter of the side's coin
};

}  // namespace glarelab
