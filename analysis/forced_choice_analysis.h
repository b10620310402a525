#pragma once
// Forced-choice preferences (Ritschel et al. 2009, Sec. 6.1 and Fig. 12 left): per scene and
// instruction (condition keys "scene" and "instruction" when present, else per condition name),
// how often each option was chosen over each other, with an exact two-sided binomial test and a
// Pearson chi-square test against no preference (df = 1), pooled over scenes per instruction as
// in "dynamic brighter than static, chi2 = 72.2"; with a "neither" answer, its share of all
// answers (3-way choices).
//
// The options of a trial are the condition values at its positions ("left", "right"); the
// chosen option is the condition value named by the response (or the response itself when it
// names an option, or "neither").
#include <functional>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"
#include "analysis/statistics.h"

namespace glarelab::analysis {

struct PairPreference {
  std::string group;     // "scene=Gem, instruction=brighter" or the condition name; "pooled: ..." when pooled
  std::string option_a;  // the option chosen more often (ties: alphabetical)
  std::string option_b;
  long chose_a = 0;
  long chose_b = 0;
  long neither = 0;
  TestResult binomial;    // chose_a of chose_a + chose_b against 1/2
  TestResult chi_square;  // (chose_a, chose_b) against equal counts
  double share_a() const;  // chose_a / (chose_a + chose_b); 0 when no choices
  double neither_share() const;  // neither / all answers
};

struct ForcedChoiceAnalysis {
  std::vector<PairPreference> groups;
  std::vector<PairPreference> pooled;  // over scenes, per instruction (or over all conditions)
  std::vector<std::string> notes;
  long trials = 0;
  bool empty() const { return trials == 0; }
};

// Trials for which `skip` is true are left to another analysis (a graded variable).
ForcedChoiceAnalysis analyse_forced_choice(const LoadedData& data,
                                           const std::function<bool(const LoadedTrial&)>& skip = {});

}  // namespace glarelab::analysis
