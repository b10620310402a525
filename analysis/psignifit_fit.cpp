#include "analysis/psignifit_fit.h"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "analysis/psignifit_posterior.h"

namespace glarelab::analysis {

namespace {

using Borders = std::array<std::array<double, 2>, kPsignifitParameters>;
using Steps = std::array<int, kPsignifitParameters>;


Steps default_grid_steps(PsignifitExperiment experiment) {
  if (experiment == PsignifitExperiment::yes_no) return {40, 40, 20, 20, 20};
  return {40, 40, 20, 1, 20};
}

Steps default_border_steps(PsignifitExperiment experiment) {
  if (experiment == PsignifitExperiment::yes_no) return {25, 30, 10, 10, 15};
  return {30, 40, 10, 1, 20};
}

void check_options(const PsignifitOptions& options) {
  if (options.experiment == PsignifitExperiment::n_afc && options.alternatives < 2)
    throw std::invalid_argument("expN must be at least 2 for an n-AFC experiment, not " + std::to_string(options.alternatives));
  if (!(options.beta_prior >= 1.0)) throw std::invalid_argument("betaPrior must be at least 1 (eta's prior is Beta(1, betaPrior))");
  if (options.credibility.empty()) throw std::invalid_argument("confP needs at least one credibility");
  for (double p : options.credibility)
    if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("confP values must lie strictly between 0 and 1");
  if (options.max_blocks < 1) throw std::invalid_argument("nblocks must be at least 1");
  if (options.pool_x_tol < 0.0 || !(options.pool_max_gap >= 0.0) || !(options.pool_max_length > 0.0))
    throw std::invalid_argument("poolxTol and poolMaxGap must not be negative, poolMaxLength must be positive");
  if (!(options.max_border_value > 0.0 && options.max_border_value < 1.0))
    throw std::invalid_argument("maxBorderValue must lie strictly between 0 and 1");
  const auto& fixed = options.fixed;
  if (fixed[1] && !(*fixed[1] > 0.0)) throw std::invalid_argument("a fixed width must be positive");
  if (fixed[2] && !(*fixed[2] >= 0.0 && *fixed[2] < 1.0)) throw std::invalid_argument("a fixed lambda must lie in [0, 1)");
  if (fixed[4] && !(*fixed[4] >= 0.0 && *fixed[4] < 1.0)) throw std::invalid_argument("a fixed eta must lie in [0, 1)");
  if (fixed[3]) {
    if (options.experiment == PsignifitExperiment::equal_asymptote)
      throw std::invalid_argument("gamma cannot be fixed for the equal-asymptote type: it equals lambda (fix lambda)");
    if (options.experiment == PsignifitExperiment::n_afc && std::abs(*fixed[3] - 1.0 / options.alternatives) > 1e-12)
      throw std::invalid_argument("gamma is 1/expN for an n-AFC experiment; fix it only for yes/no");
    if (!(*fixed[3] >= 0.0 && *fixed[3] < 1.0)) throw std::invalid_argument("a fixed gamma must lie in [0, 1)");
  }
  if (fixed[2] && fixed[3] && *fixed[2] + *fixed[3] >= 1.0)
    throw std::invalid_argument("the fixed lambda and gamma leave no room for the sigmoid (lambda + gamma >= 1)");
}

void check_data(const std::vector<PsignifitBlock>& data, bool log_space) {
  if (data.empty()) throw std::invalid_argument("no data to fit");
  for (const PsignifitBlock& block : data) {
    if (!std::isfinite(block.level)) throw std::invalid_argument("a stimulus level is not a finite number");
    if (block.trials < 1 || block.correct < 0 || block.correct > block.trials)
      throw std::invalid_argument("each block needs trials >= 1 and 0 <= correct <= trials");
    if (log_space && !(block.level > 0.0))
      throw std::invalid_argument("Weibull and logn are fitted on log levels: every level must be positive");
  }
  const auto [low, high] = std::minmax_element(data.begin(), data.end(),
                                               [](const PsignifitBlock& a, const PsignifitBlock& b) { return a.level < b.level; });
  if (!(high->level > low->level)) throw std::invalid_argument("the levels do not vary: a psychometric function cannot be fitted");
}

std::vector<double> linspace(double low, double high, int count) {
  if (count <= 1) return {high};
  std::vector<double> values(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) values[i] = low + (high - low) * i / (count - 1);
  values.back() = high;
  return values;
}

// Moves each parameter's borders in to the first and last points of a coarse grid whose
// marginal mass reaches `tolerance`, one point further out (paper section 2.5: the posterior is
// evaluated where it has mass).
Borders moved_borders(const PsignifitModel& model, const Borders& borders, const Steps& steps, double tolerance) {
  PsignifitAxes axes;
  for (int p = 0; p < kPsignifitParameters; ++p) {
    const auto [low, high] = borders[p];
    if (steps[p] >= 2 && low != high) axes[p] = linspace(low, high, steps[p]);
    else axes[p] = {0.5 * (low + high)};
  }
  const PsignifitGrid grid = psignifit_grid(model, axes);
  Borders moved{};
  for (int p = 0; p < kPsignifitParameters; ++p) {
    const std::vector<double>& x = axes[p];
    std::size_t first = x.size(), last = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (grid.marginals[p][i] * grid.weights[p][i] >= tolerance) {
        first = std::min(first, i);
        last = i;
      }
    }
    if (first == x.size()) {
      moved[p] = {x.front(), x.back()};
      continue;
    }
    moved[p] = {x[first == 0 ? 0 : first - 1], x[std::min(last + 1, x.size() - 1)]};
  }
  return moved;
}

// MAP: the grid's best point refined by Nelder-Mead within the initial borders.
PsignifitParameters maximise(const PsignifitModel& model, const PsignifitParameters& start, const Borders& borders,
                             const PsignifitOptions& options) {
  std::vector<int> free;
  for (int p = 0; p < kPsignifitParameters; ++p) {
    if (p == 3 && options.experiment != PsignifitExperiment::yes_no) continue;
    if (options.fixed[p] || !(borders[p][1] > borders[p][0])) continue;
    free.push_back(p);
  }
  PsignifitParameters best = start;
  if (free.empty()) return best;
  struct Problem {
    const PsignifitModel* model;
    PsignifitParameters point;
    const std::vector<int>* free;
  } problem{&model, start, &free};
  const auto objective = [](const std::vector<double>& x, std::vector<double>&, void* data) {
    auto* state = static_cast<Problem*>(data);
    for (std::size_t i = 0; i < x.size(); ++i) state->point[(*state->free)[i]] = x[i];
    const double value = psignifit_log_posterior(*state->model, state->point);
    return std::isfinite(value) ? -value : 1e300;
  };
  nlopt::opt optimiser(nlopt::LN_NELDERMEAD, static_cast<unsigned>(free.size()));
  std::vector<double> lower, upper, x;
  for (int p : free) {
    lower.push_back(borders[p][0]);
    upper.push_back(borders[p][1]);
    x.push_back(start[p]);
  }
  optimiser.set_lower_bounds(lower);
  optimiser.set_upper_bounds(upper);
  optimiser.set_min_objective(objective, &problem);
  optimiser.set_xtol_rel(1e-10);
  optimiser.set_ftol_abs(1e-12);
  optimiser.set_maxeval(20000);
  double value = 0.0;
  try {
    optimiser.optimize(x, value);
  } catch (const nlopt::roundoff_limited&) {
    // Reached to rounding: x holds the optimum.
  }
  for (std::size_t i = 0; i < free.size(); ++i) best[free[i]] = x[i];
  return best;
}

// Deviance of psi against the saturated model, binomial as psignifit reports it: the deviance
// residual sign(p_measured - psi) sqrt(2 (log L_saturated - log L_psi)) per block, the deviance
// the sum of their squares (McCullagh & Nelder 1989, section 2.4.3).
void set_deviance(PsignifitResult& result) {
  result.deviance = 0.0;
  result.deviance_residuals.clear();
  for (const PsignifitBlock& block : result.blocks) {
    const double psi = psignifit_psi(result.options, result.fit, block.level);
    const double k = static_cast<double>(block.correct);
    const double n = static_cast<double>(block.trials);
    const double measured = k / n;
    // 0 log 0 = 0 for the saturated model's blocks at 0 or 1.
    const double measured_log = (k > 0.0 ? k * std::log(measured) : 0.0) + (n - k > 0.0 ? (n - k) * std::log(1.0 - measured) : 0.0);
    const double predicted_log = (k > 0.0 ? k * std::log(psi) : 0.0) + (n - k > 0.0 ? (n - k) * std::log(1.0 - psi) : 0.0);
    const double sign = measured > psi ? 1.0 : (measured < psi ? -1.0 : 0.0);
    const double residual = sign * std::sqrt(std::max(0.0, 2.0 * (measured_log - predicted_log)));
    result.deviance_residuals.push_back(residual);
    result.deviance += residual * residual;
  }
}

}  // namespace

std::vector<PsignifitBlock> psignifit_pool(const std::vector<PsignifitBlock>& data, const PsignifitOptions& options) {
  std::vector<PsignifitBlock> pooled;
  std::vector<bool> counted(data.size(), false);
  for (std::size_t i = 0; i < data.size(); ++i) {
    if (counted[i]) continue;
    const double level = data[i].level;
    double weighted_level = 0.0;
    PsignifitBlock block{0.0, 0, 0};
    double span = 0.0;  // trials from block i up to block j, both included
    double gap = 0.0;   // trials of other levels since the last pooled block
    for (std::size_t j = i; j < data.size(); ++j) {
      span += static_cast<double>(data[j].trials);
      if (j > i && !(span - static_cast<double>(data[j].trials) < options.pool_max_length)) break;
      if (std::abs(data[j].level - level) <= options.pool_x_tol && !counted[j]) {
        counted[j] = true;
        block.correct += data[j].correct;
        block.trials += data[j].trials;
        weighted_level += data[j].level * static_cast<double>(data[j].trials);
        gap = 0.0;
      } else {
        gap += static_cast<double>(data[j].trials);
      }
      if (gap > options.pool_max_gap) break;
    }
    block.level = weighted_level / static_cast<double>(block.trials);
    pooled.push_back(block);
  }
  return pooled;
}

double psignifit_psi(const PsignifitOptions& options, const PsignifitParameters& parameters, double level) {
  const PsignifitSigmoidCurve curve(options.sigmoid, options.thresh_pc, options.width_alpha);
  const double x = psignifit_log_space(options.sigmoid) ? std::log(level) : level;
  const double gamma = options.experiment == PsignifitExperiment::equal_asymptote ? parameters[2] : parameters[3];
  return gamma + (1.0 - gamma - parameters[2]) * curve(x, parameters[0], parameters[1]);
}

double psignifit_threshold(const PsignifitOptions& options, const PsignifitParameters& parameters, double pc) {
  const PsignifitSigmoidCurve curve(options.sigmoid, options.thresh_pc, options.width_alpha);
  const double x = curve.inverse(pc, parameters[0], parameters[1]);
  return psignifit_log_space(options.sigmoid) ? std::exp(x) : x;
}

double psignifit_slope(const PsignifitOptions& options, const PsignifitParameters& parameters, double level) {
  const PsignifitSigmoidCurve curve(options.sigmoid, options.thresh_pc, options.width_alpha);
  const bool log_space = psignifit_log_space(options.sigmoid);
  const double x = log_space ? std::log(level) : level;
  const double gamma = options.experiment == PsignifitExperiment::equal_asymptote ? parameters[2] : parameters[3];
  // Chain rule through x = log(level) for the log-space sigmoids.
  const double dx_dlevel = log_space ? 1.0 / level : 1.0;
  return (1.0 - gamma - parameters[2]) * curve.derivative(x, parameters[0], parameters[1]) * dx_dlevel;
}

PsignifitResult psignifit_fit(const std::vector<PsignifitBlock>& data, const PsignifitOptions& options_in) {
  PsignifitResult result;
  result.options = options_in;
  PsignifitOptions& options = result.options;
  check_options(options);
  const bool log_space = psignifit_log_space(options.sigmoid);
  check_data(data, log_space);
  const Steps grid_steps = options.grid_steps.value_or(default_grid_steps(options.experiment));
  const Steps border_steps = options.border_steps.value_or(default_border_steps(options.experiment));
  options.grid_steps = grid_steps;
  options.border_steps = border_steps;
  for (int p = 0; p < kPsignifitParameters; ++p)
    if (grid_steps[p] < 1 || border_steps[p] < 1) throw std::invalid_argument("stepN and mbStepN need at least one point per parameter");
  const auto fitted = [&](double level) { return log_space ? std::log(level) : level; };

  // The stimulus range and the smallest step between levels, on the fitted axis, from the data
  // as given (before pooling) unless the range is given (paper section 2.4).
  std::set<double> levels;
  for (const PsignifitBlock& block : data) levels.insert(fitted(block.level));
  double width_min = 0.0;
  if (options.stimulus_range) {
    const auto [low, high] = *options.stimulus_range;
    if (!(high > low) || (log_space && !(low > 0.0))) throw std::invalid_argument("stimulusRange needs low < high (and low > 0 for Weibull and logn)");
    result.fitted_range = {fitted(low), fitted(high)};
    // No steps to learn from: psignifit's smallest width, 100 ulps of the range's end.
    const double end = std::abs(result.fitted_range[1]);
    width_min = 100.0 * (std::nextafter(end, std::numeric_limits<double>::infinity()) - end);
  } else {
    result.fitted_range = {*levels.begin(), *levels.rbegin()};
    width_min = std::numeric_limits<double>::infinity();
    for (auto it = std::next(levels.begin()); it != levels.end(); ++it) width_min = std::min(width_min, *it - *std::prev(it));
  }
  const double spread = result.fitted_range[1] - result.fitted_range[0];

  // Pool when a block has a single trial or there are more blocks than max_blocks.
  long most_trials = 0;
  for (const PsignifitBlock& block : data) most_trials = std::max(most_trials, block.trials);
  result.blocks = (most_trials == 1 || static_cast<int>(data.size()) > options.max_blocks) ? psignifit_pool(data, options) : data;

  PsignifitModel model{PsignifitSigmoidCurve(options.sigmoid, options.thresh_pc, options.width_alpha), options.experiment, {}, {}};
  for (PsignifitBlock block : result.blocks) {
    block.level = fitted(block.level);
    model.blocks.push_back(block);
  }
  // Widths are compared with the prior at alpha = 0.05 (the normal's width ratio).
  const PsignifitSigmoidCurve normal_05(PsignifitSigmoid::norm, 0.5, 0.05);
  const PsignifitSigmoidCurve normal_alpha(PsignifitSigmoid::norm, 0.5, options.width_alpha);
  const double width_factor = (normal_05.inverse(0.95, 0.0, 1.0) - normal_05.inverse(0.05, 0.0, 1.0)) /
                              (normal_alpha.inverse(1.0 - options.width_alpha, 0.0, 1.0) - normal_alpha.inverse(options.width_alpha, 0.0, 1.0));
  model.prior.range_low = result.fitted_range[0];
  model.prior.range_high = result.fitted_range[1];
  model.prior.width_min = width_min;
  model.prior.width_factor = width_factor;
  model.prior.beta_prior = options.beta_prior;

  // Initial borders (paper section 2.5): threshold within the range +- half its spread, width from
  // the smallest step to three spreads, lambda and a free gamma in [0, 0.5], eta in [0, 1).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Borders borders{};
  borders[0] = {result.fitted_range[0] - 0.5 * spread, result.fitted_range[1] + 0.5 * spread};
  borders[1] = {width_min, 3.0 / width_factor * spread};
  borders[2] = {0.0, 0.5};
  if (options.experiment == PsignifitExperiment::n_afc) borders[3] = {1.0 / options.alternatives, 1.0 / options.alternatives};
  else if (options.experiment == PsignifitExperiment::yes_no) borders[3] = {0.0, 0.5};
  else borders[3] = {nan, nan};
  borders[4] = {0.0, 1.0 - std::exp(-20.0)};
  for (int p = 0; p < kPsignifitParameters; ++p)
    if (options.fixed[p]) borders[p] = {*options.fixed[p], *options.fixed[p]};
  model.prior.normalise(borders);

  const Borders grid_borders = options.move_borders ? moved_borders(model, borders, border_steps, options.max_border_value) : borders;
  PsignifitAxes axes;
  for (int p = 0; p < kPsignifitParameters; ++p) {
    const auto [low, high] = grid_borders[p];
    axes[p] = low < high ? linspace(low, high, grid_steps[p]) : std::vector<double>{low};
  }
  const PsignifitGrid grid = psignifit_grid(model, axes);
  result.log_p_max = grid.log_p_max;
  result.integral = grid.integral;
  result.grid = grid.axes;
  result.marginals = grid.marginals;
  result.marginal_weights = grid.weights;
  const int gamma_source = options.experiment == PsignifitExperiment::equal_asymptote ? 2 : 3;
  for (int p = 0; p < kPsignifitParameters; ++p) {
    const int q = p == 3 ? gamma_source : p;
    double mean = 0.0;
    for (std::size_t i = 0; i < axes[q].size(); ++i) mean += grid.marginals[q][i] * grid.weights[q][i] * axes[q][i];
    result.mean_fit[p] = mean;
    for (double credibility : options.credibility)
      result.intervals[p].push_back(psignifit_percentile_interval(grid.marginals[q], axes[q], grid.weights[q], credibility));
  }
  if (options.experiment == PsignifitExperiment::equal_asymptote) {
    result.grid[3] = result.grid[2];
    result.marginals[3] = result.marginals[2];
    result.marginal_weights[3] = result.marginal_weights[2];
  }
  result.map = maximise(model, grid.best, borders, options);
  if (options.experiment == PsignifitExperiment::equal_asymptote) result.map[3] = result.map[2];
  result.fit = options.estimate_map ? result.map : result.mean_fit;
  set_deviance(result);
  return result;
}

}  // namespace glarelab::analysis
