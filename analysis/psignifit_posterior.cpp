#include "analysis/psignifit_posterior.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/parallel_for.h"

namespace glarelab::analysis {

namespace {

constexpr double kMinusInfinity = -std::numeric_limits<double>::infinity();
// Below this eta^2 the beta-binomial is numerically the binomial (psignifit's switch-over).
constexpr double kBinomialVariance = 1e-9;

double beta_one_b_density(double x, double b) {
  // Beta(1, b): b (1 - x)^(b - 1) on [0, 1].
  if (!(x >= 0.0 && x <= 1.0)) return 0.0;
  return b * std::pow(1.0 - x, b - 1.0);
}

// log of the rising factorial a (a + 1) ... (a + count - 1) = lgamma(a + count) - lgamma(a),
// as a product flushed into the log before it leaves double's range: far cheaper than lgamma.
struct LogProduct {
  double log_sum = 0.0;
  double product = 1.0;
  void multiply(double factor) {
    if (factor < 1e-50) {
      log_sum += std::log(factor);
      return;
    }
    product *= factor;
    if (product > 1e250 || product < 1e-250) {
      log_sum += std::log(product);
      product = 1.0;
    }
  }
  void rising(double a, long count) {
    for (long j = 0; j < count; ++j) multiply(a + static_cast<double>(j));
  }
  double value() const { return log_sum + std::log(product); }
};

double log_rising(double a, long count) {
  LogProduct product;
  product.rising(a, count);
  return product.value();
}

// log likelihood of all blocks for given predicted probabilities psi (paper Eq. 4-5; the
// binomial coefficients, the same for every parameter, are left out as psignifit does). A block
// without correct (or without wrong) answers contributes nothing through psi (or 1 - psi), so a
// prediction of exactly 0 or 1 costs nothing where the answers agree with it (0 log 0 = 0).
double log_likelihood(const std::vector<PsignifitBlock>& blocks, const std::vector<double>& psi, double eta,
                      double log_rising_v_total) {
  const double variance = eta * eta;
  if (variance < kBinomialVariance) {
    double sum = 0.0;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      const long k = blocks[b].correct, wrong = blocks[b].trials - blocks[b].correct;
      if (k > 0) sum += static_cast<double>(k) * std::log(psi[b]);
      if (wrong > 0) sum += static_cast<double>(wrong) * std::log(1.0 - psi[b]);
    }
    return sum;
  }
  // Beta-binomial with a = psi v, b = (1 - psi) v, v = 1/eta^2 - 1:
  //   log B(k + a, n - k + b) / B(a, b) = log rising(a, k) + log rising(b, n - k) - log rising(v, n).
  const double v = 1.0 / variance - 1.0;
  LogProduct product;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    product.rising(psi[b] * v, blocks[b].correct);
    product.rising((1.0 - psi[b]) * v, blocks[b].trials - blocks[b].correct);
  }
  return product.value() - log_rising_v_total;
}

// Whether plain products of a block's rising factorials stay in double's range at this eta
// ((v + n)^n <= 1e150), so that log_likelihood_row needs no check per factor.
bool fast_products(const std::vector<PsignifitBlock>& blocks, double eta) {
  const double variance = eta * eta;
  if (variance < kBinomialVariance) return true;
  const double v = 1.0 / variance - 1.0;
  for (const PsignifitBlock& block : blocks) {
    const double n = static_cast<double>(block.trials);
    if (n * std::log10(v + n) > 150.0) return false;
  }
  return true;
}

double log_rising_v_total(const std::vector<PsignifitBlock>& blocks, double eta) {
  const double variance = eta * eta;
  if (variance < kBinomialVariance) return 0.0;
  const double v = 1.0 / variance - 1.0;
  double total = 0.0;
  for (const PsignifitBlock& block : blocks) total += log_rising(v, block.trials);
  return total;
}

void fill_psi(const std::vector<double>& sigmoid, double lambda, double gamma, std::vector<double>& psi) {
  const double scale = 1.0 - gamma - lambda;
  for (std::size_t b = 0; b < sigmoid.size(); ++b) psi[b] = gamma + scale * sigmoid[b];
}

// The eta axis of a grid with what log_likelihood needs per value, computed once per grid.
struct EtaAxis {
  std::vector<double> eta, v, rising_total;
  std::vector<char> binomial, fast;
  std::vector<std::size_t> fast_indices;
  std::vector<double> fast_v;  // v of the fast etas, in fast_indices' order
};

EtaAxis eta_axis(const std::vector<PsignifitBlock>& blocks, const std::vector<double>& etas) {
  EtaAxis axis;
  axis.eta = etas;
  for (std::size_t i = 0; i < etas.size(); ++i) {
    const double variance = etas[i] * etas[i];
    axis.binomial.push_back(variance < kBinomialVariance ? 1 : 0);
    axis.v.push_back(variance < kBinomialVariance ? 1.0 : 1.0 / variance - 1.0);
    axis.rising_total.push_back(log_rising_v_total(blocks, etas[i]));
    axis.fast.push_back(fast_products(blocks, etas[i]) ? 1 : 0);
    if (!axis.binomial.back() && axis.fast.back()) {
      axis.fast_indices.push_back(i);
      axis.fast_v.push_back(axis.v.back());
    }
  }
  return axis;
}

// log likelihood at every eta of the axis for one set of predicted probabilities, into out.
// Per block, the rising factorials of psi v and (1 - psi) v are two independent product chains,
// and the etas are independent of each other, so the processor overlaps them.
void log_likelihood_row(const std::vector<PsignifitBlock>& blocks, const std::vector<double>& psi, const EtaAxis& axis,
                        double* out) {
  const std::size_t count = axis.fast_indices.size();
  for (std::size_t f = 0; f < count; ++f) {
    const double v = axis.fast_v[f];
    double log_sum = 0.0, product = 1.0;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      const double a = psi[b] * v, c = (1.0 - psi[b]) * v;
      const long k = blocks[b].correct, wrong = blocks[b].trials - blocks[b].correct;
      double rising_a = 1.0, rising_c = 1.0;
      for (long j = 0; j < k; ++j) rising_a *= a + static_cast<double>(j);
      for (long j = 0; j < wrong; ++j) rising_c *= c + static_cast<double>(j);
      product *= rising_a * rising_c;
      if (product > 1e150 || product < 1e-150) {
        log_sum += std::log(product);
        product = 1.0;
      }
    }
    out[axis.fast_indices[f]] = log_sum + std::log(product) - axis.rising_total[axis.fast_indices[f]];
  }
  double binomial = 0.0;
  bool binomial_done = false;
  for (std::size_t i = 0; i < axis.eta.size(); ++i) {
    if (axis.binomial[i]) {
      if (!binomial_done) binomial = log_likelihood(blocks, psi, 0.0, 0.0);
      binomial_done = true;
      out[i] = binomial;
    } else if (!axis.fast[i]) {
      out[i] = log_likelihood(blocks, psi, axis.eta[i], axis.rising_total[i]);
    }
  }
}

}  // namespace

double PsignifitPrior::density(int parameter, double x) const {
  const double spread = range_high - range_low;
  switch (parameter) {
    case 0: {
      if (x >= range_low - 0.5 * spread && x <= range_low)
        return 0.5 + 0.5 * std::cos(2.0 * std::numbers::pi * (range_low - x) / spread);
      if (x > range_low && x < range_high) return 1.0;
      if (x >= range_high && x <= range_high + 0.5 * spread)
        return 0.5 + 0.5 * std::cos(2.0 * std::numbers::pi * (x - range_high) / spread);
      return 0.0;
    }
    case 1: {
      // The pieces are added, not chosen, so that they overlap as the paper's definition does
      // when twice the smallest step exceeds the range.
      const double y = x * width_factor;
      double value = 0.0;
      if (y >= width_min && y <= 2.0 * width_min) value += 0.5 - 0.5 * std::cos(std::numbers::pi * (y - width_min) / width_min);
      if (y > 2.0 * width_min && y < spread) value += 1.0;
      if (y >= spread && y <= 3.0 * spread) value += 0.5 + 0.5 * std::cos(0.5 * std::numbers::pi * (y - spread) / spread);
      return value;
    }
    case 2:
    case 3: return beta_one_b_density(x, 10.0);
    default: return beta_one_b_density(x, beta_prior);
  }
}

double PsignifitPrior::log_density(int parameter, double value) const {
  if (flat[parameter]) return 0.0;
  const double density_value = density(parameter, value) / normaliser[parameter];
  return density_value > 0.0 ? std::log(density_value) : kMinusInfinity;
}

void PsignifitPrior::normalise(const std::array<std::array<double, 2>, kPsignifitParameters>& borders) {
  for (int p = 0; p < kPsignifitParameters; ++p) {
    const auto [low, high] = borders[p];
    if (!(std::isfinite(low) && std::isfinite(high) && high > low)) {
      flat[p] = true;
      normaliser[p] = 1.0;
      continue;
    }
    // Trapezoid rule on 1000 points over the initial borders.
    constexpr int kPoints = 1000;
    double integral = 0.0;
    double previous = density(p, low);
    for (int i = 1; i < kPoints; ++i) {
      const double x = low + (high - low) * i / (kPoints - 1);
      const double current = density(p, x);
      integral += 0.5 * (previous + current) * (high - low) / (kPoints - 1);
      previous = current;
    }
    flat[p] = false;
    normaliser[p] = integral;
  }
}

double psignifit_log_posterior(const PsignifitModel& model, const PsignifitParameters& theta) {
  const double lambda = theta[2];
  const double gamma = model.experiment == PsignifitExperiment::equal_asymptote ? lambda : theta[3];
  const double eta = theta[4];
  if (!(lambda >= 0.0 && gamma >= 0.0 && lambda + gamma <= 1.0 && eta >= 0.0 && eta <= 1.0 && theta[1] > 0.0))
    return kMinusInfinity;
  double log_prior = model.prior.log_density(0, theta[0]) + model.prior.log_density(1, theta[1]) +
                     model.prior.log_density(2, lambda) + model.prior.log_density(4, eta);
  if (model.experiment != PsignifitExperiment::equal_asymptote) log_prior += model.prior.log_density(3, gamma);
  if (!std::isfinite(log_prior)) return kMinusInfinity;
  std::vector<double> sigmoid(model.blocks.size());
  for (std::size_t b = 0; b < model.blocks.size(); ++b) sigmoid[b] = model.curve(model.blocks[b].level, theta[0], theta[1]);
  std::vector<double> psi(model.blocks.size());
  fill_psi(sigmoid, lambda, gamma, psi);
  return log_prior + log_likelihood(model.blocks, psi, eta, log_rising_v_total(model.blocks, eta));
}

std::vector<double> psignifit_axis_weights(const std::vector<double>& axis) {
  if (axis.size() < 2) return std::vector<double>(axis.size(), 1.0);
  std::vector<double> weights(axis.size(), 0.0);
  for (std::size_t i = 0; i + 1 < axis.size(); ++i) {
    const double half_cell = 0.5 * (axis[i + 1] - axis[i]);
    weights[i] += half_cell;
    weights[i + 1] += half_cell;
  }
  return weights;
}

PsignifitGrid psignifit_grid(const PsignifitModel& model, const PsignifitAxes& axes) {
  PsignifitGrid grid;
  grid.axes = axes;
  const bool equal_asymptote = model.experiment == PsignifitExperiment::equal_asymptote;
  std::array<std::size_t, kPsignifitParameters> size{};
  std::array<std::vector<double>, kPsignifitParameters> log_prior;
  for (int p = 0; p < kPsignifitParameters; ++p) {
    size[p] = axes[p].size();
    for (double value : axes[p]) log_prior[p].push_back(p == 3 && equal_asymptote ? 0.0 : model.prior.log_density(p, value));
    grid.weights[p] = psignifit_axis_weights(axes[p]);
  }
  const EtaAxis eta = eta_axis(model.blocks, axes[4]);

  const std::size_t count = size[0] * size[1] * size[2] * size[3] * size[4];
  const std::size_t slice = count / size[0];
  grid.posterior.assign(count, kMinusInfinity);
  const std::size_t blocks = model.blocks.size();
  // Threshold slices are independent and each is evaluated exactly as the serial loop would, so
  // the grid does not depend on the thread count (core/parallel_for.h).
  parallel_chunks(static_cast<int>(size[0]), static_cast<int>(resolved_threads(0)), [&](int first, int last) {
    std::vector<double> sigmoid(blocks), psi(blocks), row(size[4]);
    for (std::size_t i0 = static_cast<std::size_t>(first); i0 < static_cast<std::size_t>(last); ++i0) {
      std::size_t index = i0 * slice;
      for (std::size_t i1 = 0; i1 < size[1]; ++i1) {
        for (std::size_t b = 0; b < blocks; ++b) sigmoid[b] = model.curve(model.blocks[b].level, axes[0][i0], axes[1][i1]);
        for (std::size_t i2 = 0; i2 < size[2]; ++i2) {
          for (std::size_t i3 = 0; i3 < size[3]; ++i3) {
            const double lambda = axes[2][i2];
            const double gamma = equal_asymptote ? lambda : axes[3][i3];
            const double base = log_prior[0][i0] + log_prior[1][i1] + log_prior[2][i2] + log_prior[3][i3];
            const bool valid = std::isfinite(base) && lambda + gamma <= 1.0;
            if (!valid) {
              index += size[4];
              continue;
            }
            fill_psi(sigmoid, lambda, gamma, psi);
            log_likelihood_row(model.blocks, psi, eta, row.data());
            for (std::size_t i4 = 0; i4 < size[4]; ++i4, ++index)
              if (std::isfinite(log_prior[4][i4])) grid.posterior[index] = base + log_prior[4][i4] + row[i4];
          }
        }
      }
    }
  });

  const auto best = std::max_element(grid.posterior.begin(), grid.posterior.end());
  grid.log_p_max = *best;
  std::size_t rest = static_cast<std::size_t>(best - grid.posterior.begin());
  for (int p = kPsignifitParameters - 1; p >= 0; --p) {
    grid.best[p] = axes[p][rest % size[p]];
    rest /= size[p];
  }

  // Posterior relative to its largest point, its mass with the trapezoid weights, and the
  // marginals: the mass summed over the other parameters, divided by the parameter's own weight.
  for (int p = 0; p < kPsignifitParameters; ++p) grid.marginals[p].assign(size[p], 0.0);
  double integral = 0.0;
  std::size_t index = 0;
  for (std::size_t i0 = 0; i0 < size[0]; ++i0)
    for (std::size_t i1 = 0; i1 < size[1]; ++i1)
      for (std::size_t i2 = 0; i2 < size[2]; ++i2)
        for (std::size_t i3 = 0; i3 < size[3]; ++i3)
          for (std::size_t i4 = 0; i4 < size[4]; ++i4, ++index) {
            const double density = std::exp(grid.posterior[index] - grid.log_p_max);
            grid.posterior[index] = density;
            const double mass = density * grid.weights[0][i0] * grid.weights[1][i1] * grid.weights[2][i2] *
                                grid.weights[3][i3] * grid.weights[4][i4];
            integral += mass;
            grid.marginals[0][i0] += mass;
            grid.marginals[1][i1] += mass;
            grid.marginals[2][i2] += mass;
            grid.marginals[3][i3] += mass;
            grid.marginals[4][i4] += mass;
          }
  grid.integral = integral;
  for (double& density : grid.posterior) density /= integral;
  for (int p = 0; p < kPsignifitParameters; ++p)
    for (std::size_t i = 0; i < size[p]; ++i)
      grid.marginals[p][i] = grid.weights[p][i] > 0.0 ? grid.marginals[p][i] / integral / grid.weights[p][i] : 0.0;
  return grid;
}

PsignifitInterval psignifit_percentile_interval(const std::vector<double>& marginal, const std::vector<double>& axis,
                                                const std::vector<double>& weights, double p) {
  if (axis.size() < 2) return {axis.front(), axis.front()};
  // Each grid point holds mass marginal * weight, spread evenly over its cell, whose inner
  // edges are halfway to the neighbours and whose outer edges are the grid's ends.
  const std::size_t n = axis.size();
  std::vector<double> cumulative(n);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sum += marginal[i] * weights[i];
    cumulative[i] = sum;
  }
  const double tail = 0.5 * (1.0 - p);
  // The level where the cumulative mass reaches `target`, inside the cell that holds it.
  const auto quantile = [&](double target) {
    std::size_t i = 0;
    while (i + 1 < n && cumulative[i] < target) ++i;
    const double before = i == 0 ? 0.0 : cumulative[i - 1];
    const double cell_start = i == 0 ? axis[0] : 0.5 * (axis[i - 1] + axis[i]);
    return marginal[i] > 0.0 ? cell_start + (target - before) / marginal[i] : cell_start;
  };
  return {quantile(tail), quantile(1.0 - tail)};
}

}  // namespace glarelab::analysis
