#pragma once
// The stored form of an answered trial (docs/DATABASE.md, trials and adjustments): its row from
// the plan and the procedure's scored outcome, and the double adjustment's settings, one row per
// comparison spot. The session loop commits these; test drivers that store a procedure's trials
// without presenting them build the same rows.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "protocols/procedure.h"
#include "runner/store/result_store.h"

namespace glarelab {

TrialRecord trial_record(std::int64_t session_id, const TrialPlan& plan, const TrialOutcome& outcome,
                         std::optional<double> response_time_s, double onset_s, std::string started_utc);

std::vector<AdjustmentSetting> adjustment_settings(const TrialOutcome& outcome);

}  // namespace glarelab
