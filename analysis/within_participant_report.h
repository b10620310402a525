#pragma once
// The per-participant analysis of a graded forced choice (analysis/within_participant.h) in the
// report: which participants and sessions it includes, a table of every participant's PSE per
// group and shift from the baseline, and the group effect's sentence with the tests not run and
// why; the terminal's lines.
#include <string>

#include "analysis/graded_choice_analysis.h"

namespace glarelab::analysis {

std::string within_participant_html(const GradedChoiceAnalysis& analysis);
std::string within_participant_terminal(const GradedChoiceAnalysis& analysis);

// "8 participants (P1, P2, ...) in 8 sessions (...)": what a pooled fit pools.
std::string participants_sentence(const GradedChoiceAnalysis& analysis);

}  // namespace glarelab::analysis
