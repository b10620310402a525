#include "protocols/straylight_procedure.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "protocols/json_text.h"
#include "protocols/presentation_config.h"

namespace glarelab {
namespace {

// 17 significant digits: the stored level reads back as the same double.
std::string exact_text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

}  // namespace

StraylightProcedure::StraylightProcedure(const StraylightSpec& spec, std::uint64_t seed) : spec_(spec), seed_(seed) {
  schedule_.answers = spec.answers;
  schedule_.level_step_log10 = kStraylightLevelStepLog10;
  if (!(spec.ring_luminance_cd_m2 > 0.0)) throw std::invalid_argument("straylight: the ring's luminance must be > 0");
}

double StraylightProcedure::display_straylight() const {
  return spec_.display_glow_cd_m2 /
         (ring_straylight_constant(spec_.ring_inner_deg, spec_.ring_outer_deg) * spec_.ring_luminance_cd_m2);
}

StraylightLevel StraylightProcedure::next_level() const {
  StraylightLevel level;
  // Levels outside the compensation range the display was checked for (straylight_config.h) are
  // shown at its bound: the answers still say on which side of 2 s the bound lies.
  level.log_compensation = std::clamp(next_log_compensation(schedule_, answers_, psychometric_, seed_, display_straylight()),
                                      kStraylightMinCompensationLog10, kStraylightMaxCompensationLog10);
  level.compensation_left = compensation_on_left(seed_, static_cast<std::uint64_t>(trials_run_));
  level.compensation_cd_m2 = ring_straylight_constant(spec_.ring_inner_deg, spec_.ring_outer_deg) *
                             std::pow(10.0, level.log_compensation) * spec_.ring_luminance_cd_m2;
  return level;
}

TrialPlan StraylightProcedure::next_trial() {
  if (finished()) throw std::logic_error("straylight: next_trial after the last answer");
  const StraylightLevel level = next_level();
  TrialPlan plan;
  plan.trial_index = trials_run_;
  plan.procedure = "straylight";
  plan.condition_name = "straylight";
  plan.positions = {"left", "right"};
  plan.allowed_responses = {"left", "right"};
  plan.question = "Which half flickers more?";
  plan.intensity = level.log_compensation;
  plan.stimulus_frames = spec_.cycles * spec_.frames_per_cycle;
  plan.straylight = StraylightStimulusPlan{spec_.ring_inner_deg,      spec_.ring_outer_deg,     spec_.test_field_radius_deg,
                                           spec_.ring_luminance_cd_m2, level.compensation_cd_m2, level.compensation_left,
                                           spec_.frames_per_cycle,     spec_.display_glow_cd_m2};
  plan.condition_json = JsonObjectWriter()
                            .add("name", "straylight")
                            .add("eye", spec_.eye)
                            .add("log_compensation", exact_text(level.log_compensation))
                            .add("compensated_side", level.compensation_left ? "left" : "right")
                            .add("compensation_cd_m2", exact_text(level.compensation_cd_m2))
                            .add("ring_luminance_cd_m2", exact_text(spec_.ring_luminance_cd_m2))
                            .add("ring_inner_deg", exact_text(spec_.ring_inner_deg))
                            .add("ring_outer_deg", exact_text(spec_.ring_outer_deg))
                            .add("frames_per_cycle", std::to_string(spec_.frames_per_cycle))
                            .str();
  return plan;
}

TrialOutcome StraylightProcedure::record_response(const TrialPlan& plan, const Response& response) {
  TrialOutcome outcome;
  outcome.response = response.value;
  if (response.value == kTimeoutResponse) {
    ++trials_run_;
    return outcome;
  }
  if (response.value != "left" && response.value != "right") return outcome;
  if (!plan.intensity) throw std::invalid_argument("straylight: the trial's plan has no compensation level");
  const bool compensation_left = compensation_on_left(seed_, static_cast<std::uint64_t>(trials_run_));
  answers_.push_back({*plan.intensity, (response.value == "left") == compensation_left});
  ++trials_run_;
  return outcome;
}

StraylightEstimate StraylightProcedure::estimate() const {
  return estimate_straylight(answers_, psychometric_, display_straylight());
}

}  // namespace glarelab
