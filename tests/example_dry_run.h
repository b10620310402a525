#pragma once
// A results database for an example experiment without rendering it: the experiment's own
// procedure (make_procedure, the scenes' peaks read from their files) answered by its simulated
// observer, each trial committed as the session loop commits it (runner/session/trial_commit.cpp:
// the same record fields, the adjustment settings), with three synthetic frames per trial. The
// answers depend only on the trial plans, so they are those a rendered offscreen session gives.
#include <filesystem>
#include <string>
#include <vector>

#include "protocols/experiment.h"
#include "protocols/observer.h"
#include "protocols/procedure.h"
#include "runner/session/straylight_session.h"
#include "runner/session/trial_record.h"
#include "runner/store/result_store.h"
#include "stimuli/scene_library.h"
#include "tests/analysis_synthetic.h"

namespace glarelab::test {

// Appends one completed session per seed (participants "P<seed>") for `experiment_path`.
inline void dry_run_example(const std::string& experiment_path, const std::string& db_path,
                            const std::vector<std::uint64_t>& seeds) {
  const Experiment experiment = load_experiment(experiment_path);
  const SceneLibrary scenes(experiment.scenes, experiment.display);
  ResultStore store(db_path);
  for (const std::uint64_t seed : seeds) {
    SessionRecord session = synthetic_session("P" + std::to_string(seed), seed);
    session.experiment = experiment.name;
    session.config = resolved_config_toml(experiment);
    const std::int64_t id = store.begin_session(session);
    const auto procedure = make_procedure(experiment, scenes.peak_luminances_cd_m2());
    // A straylight measurement's participant answers through its eye (runner/session/straylight_session.h).
    Experiment seeded = experiment;
    seeded.seed = seed;
    const auto observer = experiment.procedure == "straylight" ? make_simulated_straylight_participant(seeded)
                                                               : make_simulated_observer(experiment.simulated_observer, seed);
    double onset_s = 0.0;
    while (!procedure->finished()) {
      const TrialPlan plan = procedure->next_trial();
      const Response response = observer->respond(plan);
      const TrialOutcome outcome = procedure->record_response(plan, response);
      const TrialRecord record =
          trial_record(id, plan, outcome, response.response_time_s, onset_s, "2026-01-01T00:00:00.000Z");
      store.commit_trial(record, synthetic_frames(onset_s), adjustment_settings(outcome));
      onset_s += 2.0;
    }
    store.finish_session(id, "completed");
  }
}

}  // namespace glarelab::test
