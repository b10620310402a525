#pragma once
// Double adjustment (Yoshida et al. 2008; Ritschel et al. 2009, section 6.1): a centred target
// and two comparison spots, one on each side, that the observer adjusts simultaneously in log
// steps until they match the target's brightness. Both settings are recorded (table
// adjustments) and their mean is the trial's intensity, the perceived luminance in cd/m2.
// Design: condition rows x repetitions, shuffled with the seed (stream trial_order); start values
// drawn per trial and spot (stream adjustment_start).
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "protocols/experiment.h"
#include "protocols/procedure.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// coarse_step_log10, fine_step_log10, start_range_log10 and repetitions of [procedure].
void read_adjustment_procedure(TableReader& procedure, Experiment& experiment);

std::vector<TrialPlan> build_adjustment_trials(const Experiment& experiment,
                                               const std::map<std::string, double>& source_peak_cd_m2);

// "L R": the two settings in cd/m2 as the response text (17 significant digits, so a replay of
// the stored response gives back the same doubles).
std::string format_adjustment_response(double left_cd_m2, double right_cd_m2);

// Parses "L R" (or one value for both spots): settings and their mean as intensity. Throws
// std::invalid_argument for anything else, or a setting that is not a positive luminance.
TrialOutcome score_adjustment(const TrialPlan& plan, const Response& response);

std::unique_ptr<Procedure> make_adjustment_procedure(const Experiment& experiment,
                                                     const std::map<std::string, double>& source_peak_cd_m2);

}  // namespace glarelab
