#pragma once
// The final posterior of every QUEST+ / Psi track of the loaded sessions, for `glarelab analyze`.
// A session stores its fully resolved design (sessions.config) and every answered trial; the
// posterior after the last one is rebuilt exactly as `run --resume` rebuilds it: the stored design
// parsed, its scenes and procedure made, and the stored trials replayed through the procedure in
// order (runner/session/session_setup.h, replay_done_trials), each replayed condition record
// checked against the stored one. The result is handed to analysis/ as plain data
// (analysis/quest_plus_posterior.h), since analysis/ may not build procedures.
#include <memory>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"
#include "analysis/quest_plus_posterior.h"
#include "protocols/adaptive_procedure.h"
#include "protocols/experiment.h"

namespace glarelab {

// Whether a session ran QUEST+ or Psi tracks: a trial of procedure "quest" whose condition
// record names the method quest_plus or psi.
bool runs_quest_plus(const analysis::LoadedSession& session);

// A session's stored design and its procedure with every stored trial replayed. Throws
// ConfigError (design unreadable), StoreError (a replayed trial differs from the stored one) or
// what building the scenes throws.
struct ReplayedSession {
  Experiment experiment;
  std::unique_ptr<Procedure> procedure;
};
ReplayedSession replay_stored_session(const analysis::LoadedSession& session);

// The QUEST+ / Psi tracks of a replayed adaptive procedure as report data: per parameter its grid,
// marginal posterior and the procedure's own summary (mode, mean, SD), with units from the
// track's intensity_unit.
std::vector<analysis::QuestPlusPosterior> quest_plus_posteriors_of(const AdaptiveProcedure& procedure,
                                                                   const Experiment& experiment,
                                                                   const std::string& participant_label);

// Every QUEST+ / Psi track of every loaded session. A session whose posterior cannot be rebuilt
// (its scene files moved, a stored trial that does not replay) is left out with a note naming it
// and why, appended to `notes`.
std::vector<analysis::QuestPlusPosterior> rebuild_quest_plus_posteriors(const analysis::LoadedData& data,
                                                                        std::vector<std::string>& notes);

}  // namespace glarelab
