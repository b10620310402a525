#include "runner/session/trial_record.h"

#include <utility>

namespace glarelab {

TrialRecord trial_record(std::int64_t session_id, const TrialPlan& plan, const TrialOutcome& outcome,
                         std::optional<double> response_time_s, double onset_s, std::string started_utc) {
  TrialRecord record;
  record.session_id = session_id;
  record.trial_index = plan.trial_index;
  record.block = plan.block;
  record.procedure = plan.procedure;
  record.condition = plan.condition_json;
  record.intensity = outcome.intensity ? outcome.intensity : plan.intensity;
  record.response = outcome.response;
  record.correct = outcome.correct;
  record.staircase = outcome.staircase;
  record.reversal = outcome.reversal;
  record.response_time_s = response_time_s;
  record.onset_s = onset_s;
  record.started_utc = std::move(started_utc);
  return record;
}

std::vector<AdjustmentSetting> adjustment_settings(const TrialOutcome& outcome) {
  std::vector<AdjustmentSetting> settings;
  for (std::size_t spot = 0; spot < outcome.adjustment_settings_cd_m2.size(); ++spot)
    settings.push_back({static_cast<int>(spot), outcome.adjustment_settings_cd_m2[spot]});
  return settings;
}

}  // namespace glarelab
