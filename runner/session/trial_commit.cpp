// Committing a trial: its row (scored outcome, response, onset), its adjustment settings and
// every flip it showed go to the store in one transaction, before the next trial starts.
#include <vector>

#include "runner/session/session_loop.h"
#include "runner/session/trial_record.h"

namespace glarelab {

void SessionLoop::commit(const TrialPlan& plan, const TrialRun& run, const TrialOutcome& outcome) {
  const TrialRecord record = trial_record(session_id_, plan, outcome, run.response->response_time_s, run.onset_s,
                                          utc_now_iso8601());
  store_.commit_trial(record, run.frames, adjustment_settings(outcome));
}

}  // namespace glarelab
