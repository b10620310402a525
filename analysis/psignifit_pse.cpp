#include "analysis/psignifit_pse.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace glarelab::analysis {
namespace {

// One grid point of a threshold marginal: its mass spread evenly over [low, high].
struct Cell {
  double low = 0.0;
  double high = 0.0;
  double mass = 0.0;
};

std::vector<Cell> threshold_cells(const PsignifitResult& result) {
  const std::vector<double>& x = result.grid[0];
  std::vector<Cell> cells;
  double total = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) total += result.marginals[0][i] * result.marginal_weights[0][i];
  const double step = x.size() > 1 ? x[1] - x[0] : 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double mass = result.marginals[0][i] * result.marginal_weights[0][i] / total;
    if (mass > 0.0) cells.push_back({x[i] - 0.5 * step, x[i] + 0.5 * step, mass});
  }
  return cells;
}

// R(u) = integral from -infinity to u of P(B <= v) dv for B uniform on [b0, b1] (a point when
// b0 == b1): the antiderivative that turns P(B - A <= d), A uniform on [a0, a1], into
// (R(d + a1) - R(d + a0)) / (a1 - a0).
double ramp_integral(double u, double b0, double b1) {
  if (u <= b0) return 0.0;
  if (u >= b1) return 0.5 * (b1 - b0) + (u - b1);
  return 0.5 * (u - b0) * (u - b0) / (b1 - b0);
}

double difference_cdf(const std::vector<Cell>& a, const std::vector<Cell>& b, double d) {
  double cumulative = 0.0;
  for (const Cell& ca : a)
    for (const Cell& cb : b) {
      double p = 0.0;
      if (ca.high > ca.low) {
        p = (ramp_integral(d + ca.high, cb.low, cb.high) - ramp_integral(d + ca.low, cb.low, cb.high)) / (ca.high - ca.low);
      } else {
        const double u = d + ca.low;
        p = cb.high > cb.low ? std::clamp((u - cb.low) / (cb.high - cb.low), 0.0, 1.0) : (u >= cb.low ? 1.0 : 0.0);
      }
      cumulative += ca.mass * cb.mass * p;
    }
  return cumulative;
}

}  // namespace

double PsignifitPse::probability(double x) const { return psignifit_psi(result.options, result.fit, x); }

std::optional<PsignifitPse> psignifit_pse(const std::vector<StimulusLevel>& levels,
                                          std::optional<std::array<double, 2>> stimulus_range) {
  std::vector<PsignifitBlock> blocks;
  double low = 0.0, high = 0.0;
  for (const StimulusLevel& level : levels) {
    if (level.trials <= 0) continue;
    if (blocks.empty()) low = high = level.intensity;
    low = std::min(low, level.intensity);
    high = std::max(high, level.intensity);
    blocks.push_back({level.intensity, level.correct, level.trials});
  }
  if (blocks.empty() || !(high > low)) return std::nullopt;
  PsignifitOptions options;
  options.sigmoid = PsignifitSigmoid::norm;
  options.experiment = PsignifitExperiment::yes_no;
  options.fixed[2] = 0.0;  // lambda
  options.fixed[3] = 0.0;  // gamma
  if (stimulus_range) {
    options.stimulus_range = std::array<double, 2>{std::min(low, (*stimulus_range)[0]), std::max(high, (*stimulus_range)[1])};
  }
  PsignifitPse pse;
  pse.result = psignifit_fit(blocks, options);
  pse.pse = pse.result.map[0];
  pse.pse_mean = pse.result.mean_fit[0];
  pse.width = pse.result.map[1];
  // options.credibility[0] is 0.95.
  pse.credible = {pse.result.intervals[0][0].low, pse.result.intervals[0][0].high};
  return pse;
}

Interval psignifit_pse_difference_interval(const PsignifitPse& a, const PsignifitPse& b, double credibility) {
  const std::vector<Cell> cells_a = threshold_cells(a.result);
  const std::vector<Cell> cells_b = threshold_cells(b.result);
  double lowest = 0.0, highest = 0.0;
  bool first = true;
  for (const Cell& ca : cells_a)
    for (const Cell& cb : cells_b) {
      lowest = first ? cb.low - ca.high : std::min(lowest, cb.low - ca.high);
      highest = first ? cb.high - ca.low : std::max(highest, cb.high - ca.low);
      first = false;
    }
  const auto quantile = [&](double fraction) {
    double below = lowest, above = highest;
    for (int iteration = 0; iteration < 80 && above - below > 1e-12 * std::max(1.0, std::abs(above)); ++iteration) {
      const double middle = 0.5 * (below + above);
      if (difference_cdf(cells_a, cells_b, middle) < fraction) below = middle;
      else above = middle;
    }
    return 0.5 * (below + above);
  };
  return {quantile(0.5 - 0.5 * credibility), quantile(0.5 + 0.5 * credibility)};
}

}  // namespace glarelab::analysis
