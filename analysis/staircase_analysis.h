#pragma once
// Staircases and QUEST, per participant (session) and staircase: the track, the threshold as
// the mean intensity at the last k reversals (Levitt 1971), the final QUEST placement (QUEST
// places each trial at its current threshold estimate, Watson & Pelli 1983, so the last
// placement is its estimate after the last-but-one trial), maximum-likelihood psychometric
// fits of all trials of the staircase (analysis/psychometric_fit.h), and psignifit 4's Bayesian
// fit of the same trials (analysis/psignifit_fit.h), the one the report draws.
#include <optional>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"
#include "analysis/psignifit_fit.h"
#include "analysis/psychometric_fit.h"

namespace glarelab::analysis {

struct StaircasePoint {
  int trial_index = 0;
  double intensity = 0.0;
  bool correct = false;
  bool reversal = false;
};

struct StaircaseResult {
  std::string participant_label;
  std::string name;       // staircase name (or condition name)
  std::string procedure;  // staircase | quest
  std::vector<StaircasePoint> track;
  int reversals = 0;
  std::optional<double> reversal_threshold;  // mean of the last k reversal intensities
  int reversals_used = 0;
  std::optional<double> quest_estimate;
  std::string threshold_note;  // e.g. "staircase never reversed: no reversal threshold"
  double guess_rate = 0.5;
  std::string guess_note;
  std::vector<PsychometricFit> fits;  // logistic, cumulative normal, Weibull
  // psignifit 4 (Schuett et al. 2016) on every answered trial: cumulative normal, guess rate fixed
  // at guess_rate (n-AFC when it is 1/n, else yes/no with gamma fixed), lapse and eta free, the
  // priors from the tested levels; threshold at F = 1/2. The drawn curve is its MAP. Empty (with
  // psignifit_note) when the levels do not vary.
  std::optional<PsignifitResult> psignifit;
  std::string psignifit_note;
};

// psignifit's options for a track of the given guess rate (as StaircaseResult::psignifit says);
// exposed so a check can refit the same table with `glarelab fit`.
PsignifitOptions staircase_psignifit_options(double guess_rate);

struct StaircaseOptions {
  int last_reversals = 6;       // k
  int bootstrap_samples = 200;  // per fit
  std::uint64_t seed = 1;
  unsigned threads = 0;  // fit threads; 0: one per hardware thread (results do not depend on it)
};

std::vector<StaircaseResult> analyse_staircases(const LoadedData& data, const StaircaseOptions& options);

}  // namespace glarelab::analysis
