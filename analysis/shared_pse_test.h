#pragma once
// Does the point of subjective equality differ between groups? A likelihood-ratio test of one
// PSE shared by every group against a PSE per group, each group keeping its own slope, for the
// cumulative-normal model without guess or lapse rate that the PSE fits use:
//   P(x) = Phi(beta_g (x - mu_g))     (separate)     against     P(x) = Phi(beta_g (x - mu))  (shared)
// G = 2 (ln L_separate - ln L_shared) is asymptotically chi-square with (groups - 1) degrees of
// freedom (Wilks 1938; for psychometric functions e.g. Kingdom & Prins 2016, Psychophysics, ch. 9).
//
// The maxima are found by profiling: for a fixed mu each group's log likelihood is concave in
// beta (the probit log likelihood is concave in its linear predictor, here beta (x - mu)), so a
// one-dimensional bracketing search finds it; mu is then searched on a grid over the tested range
// and a range beyond either end, and refined by Brent's method around the best grid point.
#include <string>
#include <vector>

#include "analysis/psychometric_fit.h"

namespace glarelab::analysis {

struct SharedPseTest {
  std::string unavailable;  // non-empty: why no test
  double log_likelihood_separate = 0.0;
  double log_likelihood_shared = 0.0;
  double shared_pse = 0.0;  // mu of the shared model
  double statistic = 0.0;   // G = 2 (ln L_separate - ln L_shared)
  int df = 0;               // groups - 1
  double p_value = 1.0;
  bool ok() const { return unavailable.empty(); }
};

// Each group's levels: `trials` answered, `correct` the answers for the graded side (P rising with x).
SharedPseTest shared_pse_test(const std::vector<std::vector<StimulusLevel>>& groups);

// One group's log likelihood under P(x) = Phi(beta (x - mu)), `correct` counting the answers for
// the graded side (ln Phi through erfc, precise in the lower tail).
double cumulative_normal_log_likelihood(const std::vector<StimulusLevel>& levels, double mu, double beta);

// The maximum over beta of one group's cumulative-normal log likelihood at PSE mu (beta within the
// bounds of the PSE fits); `at_bound` is set when the maximum lies at the steepest slope allowed.
double profile_log_likelihood(const std::vector<StimulusLevel>& levels, double mu, bool* at_bound = nullptr);

}  // namespace glarelab::analysis
