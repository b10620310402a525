#pragma once
// A procedure decides the trials of a session one at a time, from the responses so far, so
// adaptive procedures (staircases, QUEST) and fixed designs (forced choice, ratings) run through
// the same loop. Resuming a session replays the stored responses through a fresh procedure:
// a procedure's state depends only on the experiment (seed included) and the responses it was
// given, so the replay reaches exactly the state the interrupted run had.
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "protocols/experiment.h"
#include "protocols/trial_plan.h"

namespace glarelab {

class Procedure {
 public:
  virtual ~Procedure() = default;
  // True when no further trial is to be run.
  virtual bool finished() const = 0;
  // The plan of the next trial (trial_index = number of responses recorded so far). Calling it
  // twice without a response in between gives the same plan.
  virtual TrialPlan next_trial() = 0;
  // The plan of the trial after the one next_trial() returns (`later` trials after that one), when
  // it does not depend on the answers before it: what a session prepares while the current trial
  // runs, waits for its answer and its inter-trial interval (docs/TIMING.md, "Trials prepared
  // ahead"). Empty: not known before the answers (the default: adaptive designs place their next
  // trial by the answers), or no such trial follows. Asking does not advance the procedure.
  virtual std::optional<TrialPlan> peek_following_trial(std::size_t /*later*/ = 0) const { return std::nullopt; }
  // Scores the response to the plan last returned by next_trial() and advances the procedure.
  // A response outside the plan's allowed set (e.g. "abort") is scored but does not advance;
  // "timeout" (no answer within the response window) advances without counting as an answer.
  virtual TrialOutcome record_response(const TrialPlan& plan, const Response& response) = 0;
  // Trials the design holds when fixed in advance; for adaptive procedures the minimum (their
  // length depends on the responses).
  virtual int planned_trials() const = 0;
};

// The procedure named by experiment.procedure. source_peak_cd_m2: peak luminance of each scene.
// Throws std::invalid_argument for a design that cannot be built. A fixed design reads the
// experiment's condition rows as it plans each trial: the experiment must outlive the procedure
// (moving the Experiment keeps its rows in place).
std::unique_ptr<Procedure> make_procedure(const Experiment& experiment,
                                          const std::map<std::string, double>& source_peak_cd_m2);

}  // namespace glarelab
