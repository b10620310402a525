#pragma once
// A within-participant factor (glare mode, glare strength) analysed as one: every participant's
// own psychometric function per level of the factor (psignifit 4's posterior,
// analysis/psignifit_pse.h), the participant's own PSE shift from the baseline level with the
// central 95 % of the difference of the two posteriors, and the group's shift combined over
// participants by the summary-statistics approach to the random-effects model (Holmes & Friston
// 1998, "Generalisability, random effects and population inference", NeuroImage 7, S754): the
// per-participant shifts are the data of a one-sample t test, which is the paired t test of the
// two levels' PSEs, with the t interval mean +- t(0.975, n - 1) SD / sqrt(n).
//
// Why paired shifts and not independent groups: each participant answers every level, so the
// between-participant spread of the PSE (the largest source of variance in a PSE study) is the
// same in both levels and cancels in the difference; treating the levels as independent groups
// counts it as noise and pools participants whose PSEs differ. Why the summary statistics and not
// a fully hierarchical posterior: with the same design for every participant each shift is
// estimated with about the same precision, and then the t test on the shifts is the exact
// (normal-theory) inference on the population mean shift, its spread holding both the
// participants' differences and each one's estimation error; it needs no prior on the
// between-participant spread, which 2 to 10 participants could not inform.
//
// Tests that need more participants than there are are not run, with the reason: the t test and
// its interval need two participants with both levels; the exact Wilcoxon signed-rank test (beside
// the t test, free of the normal assumption) needs six, since with n participants its smallest
// two-sided p is 2 / 2^n (0.0625 for five).
#include <optional>
#include <string>
#include <vector>

#include "analysis/psignifit_pse.h"
#include "analysis/psychometric_fit.h"
#include "analysis/rank_tests.h"
#include "analysis/statistics.h"

namespace glarelab::analysis {

// One participant's answers at one level of the factor (a group).
struct ParticipantCell {
  std::string participant;  // the sessions' participant id
  std::string group;
  std::vector<StimulusLevel> levels;  // correct counts the answers for the graded side
  std::optional<PsignifitPse> fit;    // empty with fewer than two levels
  std::optional<double> shift;        // this PSE minus the participant's baseline PSE
  std::optional<Interval> shift_interval;  // central 95 % of the difference of the two posteriors
  long answers() const;
};

// The effect of one level against the baseline over participants.
struct WithinParticipantEffect {
  std::string group;
  std::vector<std::string> participants;  // those with a PSE at both levels
  std::vector<double> shifts;             // theirs, in that order
  double mean_shift = 0.0;
  std::optional<Interval> interval;       // 95 % t interval of the mean shift
  TestResult paired_t;                    // paired t of the PSEs (unavailable: why not run)
  WilcoxonSignedRank wilcoxon;            // exact signed-rank test of the shifts (unavailable: why not run)
};

struct WithinParticipantAnalysis {
  std::vector<std::string> participants;  // in order of appearance
  std::string baseline;
  // True when some participant answered two or more levels: the factor varies within participants.
  bool within = false;
  std::vector<ParticipantCell> cells;     // by participant, then the groups' order
  std::vector<WithinParticipantEffect> effects;  // one per non-baseline group (within designs only)
  bool empty() const { return cells.empty(); }
};

// Fits every cell and combines the shifts. `group_order` lists the groups, baseline first.
WithinParticipantAnalysis analyse_within_participants(std::vector<ParticipantCell> cells,
                                                      const std::vector<std::string>& group_order,
                                                      const std::string& baseline, unsigned threads);

// The fewest participants the exact signed-rank test is run with (2 / 2^6 = 0.031 < 0.05).
inline constexpr std::size_t kWilcoxonMinimumParticipants = 6;

}  // namespace glarelab::analysis
