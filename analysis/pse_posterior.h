#pragma once
// The posterior of the point of subjective equality (PSE) of the graded forced-choice model
// (analysis/graded_choice_analysis.h), P(x) = Phi((x - mu) / sigma), no guess and no lapse rate,
// on a grid over mu and the width w = 2 Phi^-1(0.95) sigma (the x distance from P = 0.05 to 0.95),
// with weak priors set from the tested levels after Schuett et al. 2016 ("Painfree and accurate
// Bayesian estimation of psychometric functions", Vision Research 122, 105-123; psignifit 4):
//   mu: flat over the tested range [x_min, x_max], falling as a raised cosine to 0 at half the
//       range beyond either end;
//   w:  flat in log w from twice the smallest step between levels to 3 ranges, falling as a raised
//       cosine (in w) to 0 at the smallest step and at 6 ranges.
// The 95 % credible interval of mu holds the central 95 % of its marginal; a shift mu_b - mu_a of
// two independently answered groups takes the distribution of the difference of their marginals.
//
// Why not the parametric bootstrap's percentiles or the likelihood alone: with the few answers per
// group of a short study (the demo: 10 to 12 per glare mode, 2 per level) the fitted slope is too
// steep on average, so data simulated from it vary too little and the percentile interval is too
// narrow (over the demo's 40 seeded runs the known PSE fell in it in 14 to 23 runs), and answers
// that separate perfectly have no maximum-likelihood fit at all (a quarter of the control runs),
// where the posterior, bounded by the width prior, still has an interval. Measured coverage:
// tests/pse_graded_choice_test.cpp and docs/ANALYSIS.md.
#include <optional>
#include <vector>

#include "analysis/psychometric_fit.h"

namespace glarelab::analysis {

struct PsePosterior {
  std::vector<double> mu;          // grid, ascending, evenly spaced
  std::vector<double> probability;  // marginal posterior mass of each grid point, sums to 1
  double median = 0.0;
  Interval credible;  // central 95 %
  // The median of the width's marginal as the cumulative normal's sigma (w / (2 Phi^-1(0.95))): with
  // `median`, the curve drawn for a group the maximum-likelihood fit cannot give.
  double sigma_median = 0.0;
  double probability_at(double x) const;  // Phi((x - median) / sigma_median)
};

// Empty with fewer than two distinct levels or no answers.
std::optional<PsePosterior> pse_posterior(const std::vector<StimulusLevel>& levels);

// The central 95 % interval of mu_b - mu_a, a and b independent.
Interval pse_shift_credible_interval(const PsePosterior& a, const PsePosterior& b);

// The value below which `fraction` of the posterior mass lies, each grid point's mass spread over
// its cell (half a step either side), linear within a cell.
double posterior_quantile(const PsePosterior& posterior, double fraction);

}  // namespace glarelab::analysis
