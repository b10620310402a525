#include "analysis/pse_posterior.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "analysis/shared_pse_test.h"

namespace glarelab::analysis {
namespace {

constexpr int kMuPoints = 401;
constexpr int kWidthPoints = 201;
// 2 Phi^-1(0.95): the width from P = 0.05 to P = 0.95 in units of sigma.
constexpr double kWidthPerSigma = 3.289707253902945;

// Rises as a raised cosine from 0 at `zero` to 1 at `one` (either order), 1 beyond `one`.
double ramp(double v, double zero, double one) {
  const double t = std::clamp((v - zero) / (one - zero), 0.0, 1.0);
  return 0.5 - 0.5 * std::cos(std::numbers::pi * t);
}

// The central interval of weighted values (value, mass), masses summing to `total`.
Interval central_interval(std::vector<std::pair<double, double>> weighted, double total) {
  std::sort(weighted.begin(), weighted.end());
  const auto at = [&](double fraction) {
    double below = 0.0;
    for (const auto& [value, mass] : weighted) {
      if (below + mass >= fraction * total) return value;
      below += mass;
    }
    return weighted.back().first;
  };
  return {at(0.025), at(0.975)};
}

// The value below which `fraction` of the mass lies on an evenly spaced ascending grid, each
// point's mass spread over its cell (half a step either side), linear within a cell.
double grid_quantile(const std::vector<double>& grid, const std::vector<double>& mass, double fraction) {
  const double step = grid.size() > 1 ? grid[1] - grid[0] : 0.0;
  double below = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (below + mass[i] >= fraction && mass[i] > 0.0) return grid[i] - 0.5 * step + step * (fraction - below) / mass[i];
    below += mass[i];
  }
  return grid.back() + 0.5 * step;
}

}  // namespace

double PsePosterior::probability_at(double x) const {
  return 0.5 * std::erfc(-(x - median) / sigma_median / std::numbers::sqrt2);
}

double posterior_quantile(const PsePosterior& posterior, double fraction) {
  return grid_quantile(posterior.mu, posterior.probability, fraction);
}

std::optional<PsePosterior> pse_posterior(const std::vector<StimulusLevel>& levels) {
  std::vector<double> x;
  long trials = 0;
  for (const StimulusLevel& level : levels) {
    x.push_back(level.intensity);
    trials += level.trials;
  }
  std::sort(x.begin(), x.end());
  x.erase(std::unique(x.begin(), x.end()), x.end());
  if (x.size() < 2 || trials == 0) return std::nullopt;
  const double x_min = x.front(), x_max = x.back(), range = x_max - x_min;
  double smallest_step = range;
  for (std::size_t i = 1; i < x.size(); ++i) smallest_step = std::min(smallest_step, x[i] - x[i - 1]);

  PsePosterior posterior;
  const double mu_low = x_min - 0.5 * range, mu_high = x_max + 0.5 * range;
  const double log_w_low = std::log(smallest_step), log_w_high = std::log(6.0 * range);
  std::vector<double> mu_prior(kMuPoints), log_width(kWidthPoints), log_width_prior(kWidthPoints),
      inverse_sigma(kWidthPoints);
  for (int i = 0; i < kMuPoints; ++i) {
    const double mu = mu_low + (mu_high - mu_low) * i / (kMuPoints - 1);
    posterior.mu.push_back(mu);
    mu_prior[i] = mu < x_min ? ramp(mu, mu_low, x_min) : mu > x_max ? ramp(mu, mu_high, x_max) : 1.0;
  }
  for (int j = 0; j < kWidthPoints; ++j) {
    log_width[j] = log_w_low + (log_w_high - log_w_low) * j / (kWidthPoints - 1);
    const double w = std::exp(log_width[j]);
    log_width_prior[j] = w < 2.0 * smallest_step ? ramp(w, smallest_step, 2.0 * smallest_step)
                         : w > 3.0 * range       ? ramp(w, 6.0 * range, 3.0 * range)
                                                 : 1.0;
    inverse_sigma[j] = kWidthPerSigma / w;
  }
  // Log posterior on the grid (prior zero: -infinity), then normalised from its maximum.
  std::vector<double> log_post(static_cast<std::size_t>(kMuPoints) * kWidthPoints, -std::numeric_limits<double>::infinity());
  double best = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < kMuPoints; ++i) {
    if (mu_prior[i] <= 0.0) continue;
    for (int j = 0; j < kWidthPoints; ++j) {
      if (log_width_prior[j] <= 0.0) continue;
      const double value = std::log(mu_prior[i]) + std::log(log_width_prior[j]) +
                           cumulative_normal_log_likelihood(levels, posterior.mu[i], inverse_sigma[j]);
      log_post[static_cast<std::size_t>(i) * kWidthPoints + j] = value;
      best = std::max(best, value);
    }
  }
  posterior.probability.assign(kMuPoints, 0.0);
  std::vector<double> width_probability(kWidthPoints, 0.0);
  double total = 0.0;
  for (int i = 0; i < kMuPoints; ++i)
    for (int j = 0; j < kWidthPoints; ++j) {
      const double mass = std::exp(log_post[static_cast<std::size_t>(i) * kWidthPoints + j] - best);
      posterior.probability[i] += mass;
      width_probability[j] += mass;
      total += mass;
    }
  for (double& p : posterior.probability) p /= total;
  posterior.median = posterior_quantile(posterior, 0.5);
  posterior.credible = {posterior_quantile(posterior, 0.025), posterior_quantile(posterior, 0.975)};
  // The width's median on its log grid, by the same rule as the PSE's.
  for (double& p : width_probability) p /= total;
  posterior.sigma_median = std::exp(grid_quantile(log_width, width_probability, 0.5)) / kWidthPerSigma;
  return posterior;
}

Interval pse_shift_credible_interval(const PsePosterior& a, const PsePosterior& b) {
  // Every pair of grid points, mass the product; pairs below 1e-12 of the largest product are
  // dropped (they cannot move a 2.5 % quantile).
  const double largest = *std::max_element(a.probability.begin(), a.probability.end()) *
                         *std::max_element(b.probability.begin(), b.probability.end());
  std::vector<std::pair<double, double>> differences;
  double total = 0.0;
  for (std::size_t i = 0; i < a.mu.size(); ++i)
    for (std::size_t j = 0; j < b.mu.size(); ++j) {
      const double mass = a.probability[i] * b.probability[j];
      if (mass < 1e-12 * largest) continue;
      differences.emplace_back(b.mu[j] - a.mu[i], mass);
      total += mass;
    }
  return central_interval(std::move(differences), total);
}

}  // namespace glarelab::analysis
