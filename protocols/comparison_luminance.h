#pragma once
// A trial as it would be shown with its comparison at other luminances: a staircase or QUEST trial
// at a given intensity, an adjustment trial with its spots at given settings. glarelab render uses
// it to preview any point of an adaptive track or an adjustment, not only where the procedure
// starts.
#include <string>
#include <vector>

#include "protocols/experiment.h"
#include "protocols/procedure.h"
#include "protocols/trial_plan.h"

namespace glarelab {

// `luminance_cd_m2`: one value per comparison position (TrialPlan::comparison_positions), each the
// peak luminance that position's scene is scaled to. The plan's scales, source luminances,
// intensity (adaptive) or start settings (adjustment) and correct answer follow. Throws
// std::invalid_argument when the plan has no comparison (fixed designs), when the count differs,
// or for a luminance that is not finite and positive.
TrialPlan with_comparison_luminance(TrialPlan plan, const std::vector<double>& luminance_cd_m2);

// A preview of the condition named `condition` (glarelab render): a procedure that chooses its row
// with the intensity (QUEST+, Psi) is asked to show it on the next trial of its track
// (AdaptiveProcedure::show_row_on_its_tracks_next_trial); any other design shows each of its rows
// as a session does.
void show_condition_in_preview(Procedure& procedure, const Experiment& experiment, const std::string& condition);
// What show_condition_in_preview changed of the trial the procedure planned last, in words (the
// row its track chose instead); empty when it changed nothing.
std::string preview_note(const Procedure& procedure);

// Why no session of the design shows the condition named `condition`, in words (a row in no block
// of [[blocks]], or in no track of an adaptive procedure); nothing when some session shows it.
std::string why_no_session_shows(const Experiment& experiment, const std::string& condition);

}  // namespace glarelab
