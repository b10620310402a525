#include "runner/cli/straylight_measurements.h"

#include <exception>

#include "protocols/straylight_model.h"
#include "runner/session/straylight_session.h"

namespace glarelab {

std::vector<analysis::StraylightMeasurement> rebuild_straylight_measurements(const analysis::LoadedData& data,
                                                                             std::vector<std::string>& notes) {
  std::vector<analysis::StraylightMeasurement> all;
  for (const analysis::LoadedSession& session : data.sessions) {
    std::vector<TrialRecord> trials;
    for (const analysis::LoadedTrial& trial : session.trials) trials.push_back(trial.record);
    try {
      const std::optional<StoredStraylight> stored = replay_straylight(session.record, trials, session.database);
      if (!stored) continue;
      analysis::StraylightMeasurement m;
      m.participant_label = session.label;
      m.eye = stored->eye;
      m.answers = stored->answers;
      m.log_s = stored->estimate.log_s;
      m.esd_log10 = stored->estimate.esd_log10;
      m.unreliable = stored->estimate.unreliable;
      m.esd_limit_log10 = kStraylightUnreliableEsdLog10;
      m.age_years = stored->age_years;
      m.age_norm_log10 = straylight_age_norm_log10(stored->age_years);
      m.age_norm_sd_log10 = kStraylightAgeNormSdLog10;
      m.grid_log_s = stored->estimate.likelihood.log_s;
      m.likelihood = stored->estimate.likelihood.normalised;
      all.push_back(std::move(m));
    } catch (const std::exception& error) {
      // A session that does not replay costs its own measurement, not the rest of the report.
      notes.push_back("session " + session.label + ": the straylight estimate was not rebuilt: " + error.what());
    }
  }
  return all;
}

}  // namespace glarelab
