#pragma once
// Two-alternative forced choice, side by side or in two intervals ("which light is brighter?").
// The design: every condition row x repetitions x (both side assignments when counterbalanced),
// shuffled with the session seed (stream trial_order), so the order is reproducible.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "protocols/experiment.h"
#include "protocols/procedure.h"
#include "protocols/trial_plan.h"

namespace glarelab {

// The positions of the two alternatives: {"left", "right"} side by side, {"first", "second"} for
// two intervals one after the other (layout "sequential"). Trial records name the scene shown at
// each position under these keys.
const std::vector<std::string>& forced_choice_positions(const ForcedChoiceSpec& spec);
// The default responses: one per position, plus "neither" with three alternatives.
std::vector<std::string> default_responses_for(const ForcedChoiceSpec& spec);

// source_peak_cd_m2: peak luminance of each scene, in cd/m2 (from the scene images).
// Condition rows name their two scenes in columns "scene_a" and "scene_b".
std::vector<TrialPlan> build_forced_choice_trials(const Experiment& experiment,
                                                  const std::map<std::string, double>& source_peak_cd_m2);
// The same design as a procedure that plans each trial when the session reaches it (from the row
// and side the design's order holds for it), with the same plans build_forced_choice_trials
// gives. It reads the experiment's condition rows then: the experiment must outlive it (moving
// the Experiment keeps the rows where they are).
std::unique_ptr<Procedure> make_forced_choice_procedure(const Experiment& experiment,
                                                        const std::map<std::string, double>& source_peak_cd_m2);

// Scores a response: correct when it names the position of correct_response; NULL when no
// answer is right.
TrialOutcome score_forced_choice(const TrialPlan& plan, const Response& response);

}  // namespace glarelab
