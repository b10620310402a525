#pragma once
// Double adjustment (Ritschel et al. 2009, Sec. 6.1 and Fig. 12 right; Yoshida et al. 2008):
// the perceived luminance of a trial is the mean of its adjusted spots (table `adjustments`,
// schema version 2) or, without that table, the trial's intensity (the adjusted value) or its
// numeric response. Per condition and target intensity: the mean over participants of each
// participant's mean, with its standard error; per target, a one-way repeated-measures ANOVA
// across conditions (Greenhouse-Geisser corrected for 3+ levels) and paired t-tests between
// every two conditions.
//
// The condition is the condition key "glare" (else "condition", else "name"); the target
// intensity is the key "target_cd_m2" (else "target"; else one target for all trials).
#include <string>
#include <vector>

#include "analysis/loaded_database.h"
#include "analysis/statistics.h"

namespace glarelab::analysis {

struct AdjustmentCell {
  std::string condition;
  std::string target;
  MeanSe perceived;  // over participants
};

struct PairedComparison {
  std::string target;
  std::string condition_a;
  std::string condition_b;
  std::size_t participants = 0;
  TestResult t_test;
};

struct AdjustmentAnova {
  std::string target;
  std::vector<std::string> conditions;
  RepeatedMeasuresAnova anova;
};

struct AdjustmentAnalysis {
  std::vector<std::string> conditions;  // first-seen order
  std::vector<std::string> targets;
  std::vector<AdjustmentCell> cells;
  std::vector<AdjustmentAnova> anovas;
  std::vector<PairedComparison> paired;
  std::vector<std::string> notes;
  long trials = 0;
  bool empty() const { return trials == 0; }
};

AdjustmentAnalysis analyse_adjustments(const LoadedData& data);

}  // namespace glarelab::analysis
