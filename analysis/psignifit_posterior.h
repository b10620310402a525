#pragma once
// The posterior of a psignifit 4 fit (Schütt et al. 2016, section 2.3) on a grid and at single
// points: the beta-binomial likelihood (Eq. 4-5) times the standard priors (section 2.4, Fig. 5):
//   threshold: flat over the stimulus range, falling to 0 with a raised cosine over half the range
//              beyond each end;
//   width:     rising with a raised cosine from the smallest step between levels to twice it,
//              flat up to the stimulus range, falling to 0 with a raised cosine at 3 ranges
//              (the width scaled to alpha = 0.05 for another widthalpha);
//   lambda, gamma: Beta(1, 10);  eta: Beta(1, betaPrior).
// Each prior is normalised over the parameter's initial borders (trapezoid rule on 1000 points),
// as psignifit does, so that log posteriors are comparable between fits of the same data.
#include <array>
#include <vector>

#include "analysis/psignifit_fit.h"
#include "analysis/psignifit_sigmoid.h"

namespace glarelab::analysis {

using PsignifitAxes = std::array<std::vector<double>, kPsignifitParameters>;

struct PsignifitPrior {
  double range_low = 0.0;   // the stimulus range on the fitted axis
  double range_high = 1.0;
  double width_min = 0.0;   // the smallest step between levels on the fitted axis
  double width_factor = 1.0;  // widths are compared at alpha = 0.05: w * factor
  double beta_prior = 10.0;
  std::array<double, kPsignifitParameters> normaliser{1.0, 1.0, 1.0, 1.0, 1.0};
  std::array<bool, kPsignifitParameters> flat{};  // a fixed parameter: prior 1

  // Unnormalised prior density of one parameter.
  double density(int parameter, double value) const;
  // log of the normalised prior (-inf outside its support).
  double log_density(int parameter, double value) const;
  // Normalises over borders[parameter] = {low, high} (flat where low == high or not finite).
  void normalise(const std::array<std::array<double, 2>, kPsignifitParameters>& borders);
};

struct PsignifitModel {
  PsignifitSigmoidCurve curve;
  PsignifitExperiment experiment;
  std::vector<PsignifitBlock> blocks;  // levels on the fitted axis
  PsignifitPrior prior;
};

// log posterior (unnormalised) at one parameter point; gamma is ignored for the equal-asymptote
// type (it equals lambda). -inf where the prior is 0 or a level's predicted probability is 0 or 1.
double psignifit_log_posterior(const PsignifitModel& model, const PsignifitParameters& parameters);

struct PsignifitGrid {
  PsignifitAxes axes;
  std::vector<double> posterior;  // normalised density, index (((i0 n1 + i1) n2 + i2) n3 + i3) n4 + i4
  double log_p_max = 0.0;
  double integral = 0.0;  // sum of weight * exp(log posterior - log_p_max)
  std::array<std::vector<double>, kPsignifitParameters> marginals;
  std::array<std::vector<double>, kPsignifitParameters> weights;  // 1D trapezoid weights (1 for a single point)
  PsignifitParameters best{};  // the grid point of largest posterior
};

PsignifitGrid psignifit_grid(const PsignifitModel& model, const PsignifitAxes& axes);

// Trapezoid weights of one axis (1 for a single point).
std::vector<double> psignifit_axis_weights(const std::vector<double>& axis);

// Credible interval from a marginal: the (1 - p)/2 and (1 + p)/2 quantiles of the piecewise
// constant density that gives each grid point its mass over the cell around it.
PsignifitInterval psignifit_percentile_interval(const std::vector<double>& marginal, const std::vector<double>& axis,
                                                const std::vector<double>& weights, double p);

}  // namespace glarelab::analysis
