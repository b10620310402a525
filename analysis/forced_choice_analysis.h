#pragma once
// Forced-choice preferences (Ritschel et al. 2009, Sec. 6.1 and Fig. 12 left): per scene and
// instruction (condition keys "scene" and "instruction" when present, else per condition name),
// how often each option was chosen over each other with its Clopper-Pearson 95 % interval, with an
// exact two-sided binomial test and, from 10 answers (expected counts of 5, Cochran 1954), a
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
  TestResult chi_square;  // (chose_a, chose_b) against equal counts; not computed below kChiSquareMinimumAnswers
  ProportionInterval share_a_interval;  // Clopper-Pearson 95 % interval of share_a (0 to 1 without choices)
  double share_a() const;  // chose_a / (chose_a + chose_b); 0 when no choices
  double neither_share() const;  // neither / all answers
};

// Percent correct of the scored trials (a stored `correct` of 0 or 1: the task had a right answer)
// of one group, or of all of them: the share with its Clopper-Pearson 95 % interval and the exact
// two-sided binomial test against chance (1/2 with two options).
struct ScoredShare {
  std::string group;  // as PairPreference::group; "all scored trials" for the total
  long correct = 0;
  long trials = 0;
  ProportionInterval interval;
  TestResult binomial;
  double percent() const { return trials > 0 ? 100.0 * static_cast<double>(correct) / static_cast<double>(trials) : 0.0; }
};

struct ForcedChoiceAnalysis {
  std::vector<PairPreference> groups;
  // Over every scored forced-choice trial, a graded variable's too: per group (up to 8 groups),
  // then the total when there is more than one group; empty without scored trials.
  std::vector<ScoredShare> scored;
  std::vector<PairPreference> pooled;  // over scenes, per instruction (or over all conditions)
  std::vector<std::string> notes;
  long trials = 0;
  bool empty() const { return trials == 0; }
};

// Trials for which `skip` is true are left to another analysis (a graded variable).
ForcedChoiceAnalysis analyse_forced_choice(const LoadedData& data,
                                           const std::function<bool(const LoadedTrial&)>& skip = {});

}  // namespace glarelab::analysis
