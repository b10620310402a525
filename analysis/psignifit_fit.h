#pragma once
// Bayesian psychometric function fits as psignifit 4 makes them (Schütt, Harmeling, Macke &
// Wichmann 2016, Vision Research 122, 105-123; "the paper" below):
//   psi(x) = gamma + (1 - gamma - lambda) F(x; m, w)                              (paper Eq. 1)
// with F one of the sigmoids of analysis/psignifit_sigmoid.h, threshold m, width w, lapse rate
// lambda, guess rate gamma (1/expN for n-AFC, free for yes/no, equal to lambda for the
// equal-asymptote type), and the beta-binomial overdispersion eta (paper section 2.2, Eq. 4-5):
// the success probability of a block varies with variance eta^2 psi (1 - psi), eta = 0 being
// the binomial model. The posterior (paper section 2.3) is the product of the likelihood and
// the standard priors set from the stimulus range (analysis/psignifit_posterior.h), evaluated on
// a grid of 40 x 40 x 20 x 20 x 20 points whose borders are first moved in to where the
// posterior has mass (paper section 2.5). From the grid: the marginals, the posterior means and
// the credible intervals; the MAP estimate is the grid's best point refined by a local search.
// Parameters are always in psignifit's order: threshold, width, lambda, gamma, eta.
#include <array>
#include <limits>
#include <optional>
#include <vector>

#include "analysis/psignifit_sigmoid.h"

namespace glarelab::analysis {

enum class PsignifitExperiment { n_afc, yes_no, equal_asymptote };

inline constexpr int kPsignifitParameters = 5;  // threshold, width, lambda, gamma, eta
using PsignifitParameters = std::array<double, kPsignifitParameters>;

// One block of trials at a stimulus level (in stimulus units, also for Weibull and logn).
struct PsignifitBlock {
  double level = 0.0;
  long correct = 0;  // correct (n-AFC) or "yes" (yes/no) answers
  long trials = 0;
};

struct PsignifitOptions {
  PsignifitSigmoid sigmoid = PsignifitSigmoid::norm;                 // sigmoidName
  PsignifitExperiment experiment = PsignifitExperiment::yes_no;      // expType
  int alternatives = 2;                                              // expN (n-AFC)
  double thresh_pc = 0.5;                                            // threshPC
  double width_alpha = 0.05;                                         // widthalpha
  double beta_prior = 10.0;                                          // betaPrior: eta's prior Beta(1, betaPrior)
  bool estimate_map = true;                                          // estimateType MAP (true) or mean
  std::array<std::optional<double>, kPsignifitParameters> fixed{};  // fixedPars
  std::vector<double> credibility = {0.95, 0.9, 0.68};               // confP
  // Pooling (psignifit's poolData): blocks within pool_x_tol of a block's level join it unless
  // more than pool_max_gap trials of other levels came between or the block would span more
  // than pool_max_length trials. Done when a block has one trial or there are more than
  // max_blocks blocks.
  double pool_x_tol = 0.0;                                                   // poolxTol
  double pool_max_gap = std::numeric_limits<double>::infinity();             // poolMaxGap
  double pool_max_length = std::numeric_limits<double>::infinity();          // poolMaxLength
  int max_blocks = 25;                                                       // nblocks
  // The range the stimulus could take (stimulus units); unset: the data's range.
  std::optional<std::array<double, 2>> stimulus_range;                       // stimulusRange
  // Grid sizes; unset: psignifit's for the experiment type.
  std::optional<std::array<int, kPsignifitParameters>> grid_steps;           // stepN
  std::optional<std::array<int, kPsignifitParameters>> border_steps;         // mbStepN
  double max_border_value = 1e-5;                                            // maxBorderValue
  bool move_borders = true;                                                  // moveBorders
  // The parameters simulated data were drawn with, when known (psignifit's test cases record them
  // as theta0): not used by the fit, carried into the result beside the estimates.
  std::optional<PsignifitParameters> generating_parameters;                  // theta0
};

// A credible interval at one credibility.
struct PsignifitInterval {
  double low = 0.0;
  double high = 0.0;
};

struct PsignifitResult {
  PsignifitParameters fit{};       // the estimate estimateType asks for (MAP or posterior mean)
  PsignifitParameters map{};       // maximum a posteriori
  PsignifitParameters mean_fit{};  // posterior means from the marginals
  // [parameter][credibility index] as options.credibility orders them.
  std::array<std::vector<PsignifitInterval>, kPsignifitParameters> intervals;
  double deviance = 0.0;               // binomial deviance of `fit` against the saturated model
  std::vector<double> deviance_residuals;
  double log_p_max = 0.0;              // the grid's largest log posterior (unnormalised)
  double integral = 0.0;               // the grid's posterior mass relative to its largest point
  std::vector<PsignifitBlock> blocks;  // the data after pooling
  std::array<std::vector<double>, kPsignifitParameters> grid;             // the grid per parameter
  std::array<std::vector<double>, kPsignifitParameters> marginals;        // posterior density on it
  std::array<std::vector<double>, kPsignifitParameters> marginal_weights; // quadrature weights
  PsignifitOptions options;            // the options with the defaults filled in
  std::array<double, 2> fitted_range{};  // the stimulus range on the fitted axis (log for Weibull, logn)
};

// Fits. Throws std::invalid_argument for data or options that cannot be fitted (no spread of
// levels, counts out of range, non-positive levels for Weibull or logn, a fixed value outside
// what the experiment type allows).
PsignifitResult psignifit_fit(const std::vector<PsignifitBlock>& data, const PsignifitOptions& options);

// psignifit's pooling of blocks (see PsignifitOptions), in data order.
std::vector<PsignifitBlock> psignifit_pool(const std::vector<PsignifitBlock>& data, const PsignifitOptions& options);

// psi(level) with the given parameters; level in stimulus units.
double psignifit_psi(const PsignifitOptions& options, const PsignifitParameters& parameters, double level);
// The stimulus level (stimulus units) where the unscaled sigmoid F reaches pc.
double psignifit_threshold(const PsignifitOptions& options, const PsignifitParameters& parameters, double pc);
// dpsi/dlevel at a level (stimulus units).
double psignifit_slope(const PsignifitOptions& options, const PsignifitParameters& parameters, double level);

}  // namespace glarelab::analysis
