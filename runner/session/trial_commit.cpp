// Committing a trial: its row (scored outcome, response, onset), its adjustment settings and
// every flip it showed go to the store in one transaction, before the next trial starts.
#include <vector>

#include "runner/session/session_loop.h"

namespace glarelab {

void SessionLoop::commit(const TrialPlan& plan, const TrialRun& run, const TrialOutcome& outcome) {
  TrialRecord record;
  record.session_id = session_id_;
  record.trial_index = plan.trial_index;
  record.block = plan.block;
  record.procedure = plan.procedure;
  record.condition = plan.condition_json;
  record.intensity = outcome.intensity ? outcome.intensity : plan.intensity;
  record.response = outcome.response;
  record.correct = outcome.correct;
  record.staircase = outcome.staircase;
  record.reversal = outcome.reversal;
  record.response_time_s = run.response->response_time_s;
  record.onset_s = run.onset_s;
  record.started_utc = utc_now_iso8601();
  std::vector<AdjustmentSetting> settings;
  for (std::size_t spot = 0; spot < outcome.adjustment_settings_cd_m2.size(); ++spot)
    settings.push_back({static_cast<int>(spot), outcome.adjustment_settings_cd_m2[spot]});
  store_.commit_trial(record, run.frames, settings);
}

}  // namespace glarelab
