#pragma once
// Forced choice with a graded variable (Spencer et al. 1995, Figs. 12-13, asked with two sides;
// Ritschel et al. 2009, Sec. 6.1): the proportion of answers naming scene_b against a numeric
// condition column, one psychometric function per glare group, its point of subjective equality
// (PSE), the PSE shift of each group from the baseline group, and a likelihood-ratio test of one
// shared PSE against one per group (analysis/shared_pse_test.h).
//
// Which trials: forced-choice trials whose condition has a numeric column taking at least three
// values over them: the graded variable, the first such column in the stored order (e.g.
// `luminance_ratio`, scene_b over scene_a; `glare_gain`). A column whose name contains "ratio" is
// analysed on a log10 axis (a ratio's PSE and shift are then read as ratios: 10^x).
// Which side is scene_b: the position (left/right or first/second) showing scene_b; with the same
// scene on both sides, the position showing glare_b. Answers naming neither position ("neither",
// abort) are counted but not fitted, as in the PSE analysis (analysis/pse_analysis.h).
// Groups: the glare mode of the condition (`glare`), else of scene_a (`glare_a`, with `/ glare_b`
// when glare_b is not the same in every trial), else one group; the baseline is "control" when a
// group has that name, else the first group; groups are listed baseline first, then alphabetically.
//
// Per participant (the sessions' participant id, over every session and database loaded):
// psignifit 4 fits per group, and when the groups vary within participants the shifts combined
// over participants (analysis/within_participant.h).
//
// Fit: cumulative normal, no guess and no lapse rate (P runs from 0 to 1 and a one-sided lapse
// would move the 50 % point), maximum likelihood (analysis/psychometric_fit.h). The PSE's and the
// shift's 95 % intervals are Bayesian credible intervals on a grid with weak priors
// (analysis/pse_posterior.h, which says why not the bootstrap's percentiles); the slope's is the
// parametric bootstrap's.
#include <optional>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"
#include "analysis/pse_posterior.h"
#include "analysis/psignifit_pse.h"
#include "analysis/psychometric_fit.h"
#include "analysis/shared_pse_test.h"
#include "analysis/within_participant.h"

namespace glarelab::analysis {

struct GradedChoiceGroup {
  std::string name;
  std::vector<StimulusLevel> levels;  // x on the analysis axis; correct = answers naming scene_b
  long neither = 0;                   // answers naming no side (left out of the fit)
  PsychometricFit fit;                // ML: its threshold is the PSE; its bootstrap gives the slope's interval
  std::optional<PsePosterior> posterior;  // of the PSE (pse_posterior.h): its 95 % credible interval
  // psignifit 4's fit of the pooled levels (analysis/psignifit_pse.h), the one the per-participant
  // PSEs use: the figure draws its MAP curve, its PSE and the threshold's 95 % credible interval.
  std::optional<PsignifitPse> psignifit;
  std::optional<double> shift;        // PSE - the baseline's PSE, on the axis (ML; posterior medians without a fit)
  std::optional<Interval> shift_interval;  // 95 % credible interval of the difference
  // The PSE shown: the ML threshold, else (answers that separate perfectly) the posterior median.
  std::optional<double> pse() const;
};

struct GradedChoiceAnalysis {
  std::string variable;    // the condition column
  bool log10_axis = false;  // x = log10(variable)
  std::string baseline;    // the group shifts are measured from
  std::vector<GradedChoiceGroup> groups;
  SharedPseTest shared_pse;  // only with two or more groups
  // The groups above pool every participant; this is the analysis per participant, and of the
  // group factor within participants when it varies within them (analysis/within_participant.h).
  WithinParticipantAnalysis within;
  std::vector<std::string> sessions;  // the labels of the sessions whose trials entered
  std::vector<std::string> notes;
  long trials = 0;
  bool empty() const { return groups.empty(); }
  // "log10 luminance_ratio" or the column name.
  std::string axis_label() const;
};

struct GradedChoiceOptions {
  int bootstrap_samples = 200;
  std::uint64_t seed = 1;
  unsigned threads = 0;
};

GradedChoiceAnalysis analyse_graded_choice(const LoadedData& data, const GradedChoiceOptions& options);

// True when the forced-choice trial enters the graded analysis of `analysis`.
bool is_graded_trial(const LoadedTrial& trial, const GradedChoiceAnalysis& analysis);

}  // namespace glarelab::analysis
