#pragma once
// Pairwise designs (Ritschel et al. 2009, Sec. 6.1: every pair of glare modes): per pooled group of
// the forced-choice analysis (an instruction, over scenes), the preference matrix (how often each
// option was chosen over each other) and the Bradley-Terry scale of the options
// (analysis/bradley_terry.h) with 95 % Wald intervals, lambda +- 1.96 SE. The reference option (at
// 0) is "control" when it is one of them, else the first in alphabetical order. Groups with three
// or more options, every pair of them compared, only: with two, the scale is the log odds of the
// one pair the table already tests; a star of pairs around one reference is no pairwise design.
#include <string>
#include <vector>

#include "analysis/bradley_terry.h"
#include "analysis/forced_choice_analysis.h"
#include "analysis/svg_plot.h"

namespace glarelab::analysis {

struct PairedScale {
  std::string group;                    // the pooled group ("pooled: instruction=brighter")
  std::vector<std::string> options;     // alphabetical
  std::vector<std::vector<long>> wins;  // wins[i][j]: option i chosen over option j
  BradleyTerryScale scale;
};

std::vector<PairedScale> scale_pooled_pairs(const ForcedChoiceAnalysis& analysis);

// The preference matrix as a figure: cell (row i, column j) shaded by the share of choices of i
// over j, with that share and the counts written in it.
std::string preference_matrix_svg(const PairedScale& paired);

// The scale as a figure: each option's log worth with its 95 % interval.
std::string bradley_terry_svg(const PairedScale& paired);

}  // namespace glarelab::analysis
