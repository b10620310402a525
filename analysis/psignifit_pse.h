#pragma once
// A point of subjective equality (PSE) from psignifit 4's posterior (analysis/psignifit_fit.h;
// Schuett, Harmeling, Macke & Wichmann 2016, Vision Research 122, 105-123): a yes/no fit of the
// cumulative normal with the guess and lapse rates fixed at 0 (the answers for one side run from
// 0 to 1, and a lapse at one end only would move the 50 % point), the overdispersion eta free
// (paper Eq. 4-5), the threshold at F = 1/2 and the paper's priors set from the stimulus range.
// The PSE is psignifit's default estimate (the MAP, paper section 2.6); its interval the central
// 95 % of the threshold's marginal (psignifit's `percentiles`). A posterior has no separation
// problem: answers that separate perfectly still give an estimate and a proper interval, the
// width prior bounding how steep the function may be.
//
// With guess and lapse fixed the grid is 40 x 40 x 1 x 1 x 20 points (psignifit's own sizes for
// the free parameters), a few milliseconds per fit.
#include <array>
#include <optional>
#include <vector>

#include "analysis/psignifit_fit.h"
#include "analysis/psychometric_fit.h"

namespace glarelab::analysis {

struct PsignifitPse {
  PsignifitResult result;
  double pse = 0.0;        // MAP threshold (F = 1/2)
  double pse_mean = 0.0;   // posterior-mean threshold
  Interval credible;       // central 95 % of the threshold's marginal
  double width = 0.0;      // MAP width, F = 0.05 to 0.95 (the stimulus distance)
  double probability(double x) const;  // psi(x) at the MAP
};

// The PSE fit of levels whose `correct` counts the answers for the graded side. `stimulus_range`
// widens the priors' range beyond the tested levels (adaptive tracks: the range the track could
// take). Empty with fewer than two distinct levels or no answers.
std::optional<PsignifitPse> psignifit_pse(const std::vector<StimulusLevel>& levels,
                                          std::optional<std::array<double, 2>> stimulus_range = std::nullopt);

// The central `credibility` interval of pse_b - pse_a for two independently answered fits: the
// difference of the two threshold marginals, each grid point's mass spread evenly over its cell
// (as psignifit's percentiles spread it), found by bisection on the difference's cumulative.
Interval psignifit_pse_difference_interval(const PsignifitPse& a, const PsignifitPse& b, double credibility = 0.95);

}  // namespace glarelab::analysis
