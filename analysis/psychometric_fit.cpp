#include "analysis/psychometric_fit.h"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlopt.hpp>

#include "core/random.h"

namespace glarelab::analysis {
namespace {

constexpr double kProbabilityFloor = 1e-12;  // keeps log(psi) finite at the bounds

struct Bounds {
  double alpha_low, alpha_high, log_beta_low, log_beta_high;
};

Bounds parameter_bounds(PsychometricShape shape, double x_min, double x_max) {
  const double span = x_max - x_min;
  if (shape == PsychometricShape::weibull) {
    // Threshold within a factor 10 around the tested range; slope 0.1 (very shallow) to 100.
    return {x_min / 10.0, x_max * 10.0, std::log(0.1), std::log(100.0)};
  }
  // Slope in units of the tested range: from a function that rises over 1000 ranges to one that
  // rises within 1/1000 of the range; threshold within a range beyond either end.
  return {x_min - span, x_max + span, std::log(1e-3 / span), std::log(1e3 / span)};
}

struct Problem {
  const std::vector<StimulusLevel>* levels;
  PsychometricShape shape;
  double guess;
};

double negative_log_likelihood(const Problem& problem, double alpha, double beta, double lapse) {
  double sum = 0.0;
  for (const StimulusLevel& level : *problem.levels) {
    const double psi = std::clamp(psychometric_probability(problem.shape, level.intensity, alpha, beta, problem.guess, lapse),
                                  kProbabilityFloor, 1.0 - kProbabilityFloor);
    // A zero count contributes exactly (-)0 (psi is clamped, so the log is finite): skipping its log
    // leaves the sum bit-identical and saves a transcendental call at the many all-correct or
    // all-wrong levels of a staircase.
    const long wrong = level.trials - level.correct;
    const double right_term = level.correct > 0 ? static_cast<double>(level.correct) * std::log(psi) : 0.0;
    const double wrong_term = wrong > 0 ? static_cast<double>(wrong) * std::log1p(-psi) : 0.0;
    sum += right_term + wrong_term;
  }
  return -sum;
}

double objective(unsigned, const double* x, double*, void* data) {
  const Problem& problem = *static_cast<const Problem*>(data);
  return negative_log_likelihood(problem, x[0], std::exp(x[1]), x[2]);
}

// k ln(k / e) with 0 ln 0 = 0 (deviance terms).
double deviance_term(double observed, double expected) {
  return observed > 0.0 ? observed * std::log(observed / expected) : 0.0;
}

std::string shortest(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

}  // namespace

Interval percentile_interval(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  auto at = [&](double q) {
    const double position = q * static_cast<double>(values.size() - 1);
    const auto below = static_cast<std::size_t>(std::floor(position));
    const std::size_t above = std::min(below + 1, values.size() - 1);
    const double fraction = position - static_cast<double>(below);
    return values[below] + fraction * (values[above] - values[below]);
  };
  return {at(0.025), at(0.975)};
}

namespace {

PsychometricFit fit_point(const std::vector<StimulusLevel>& levels, const PsychometricFitOptions& options) {
  PsychometricFit fit;
  fit.shape = options.shape;
  fit.guess = options.guess_rate;
  long correct = 0;
  for (const StimulusLevel& level : levels) {
    fit.total_trials += level.trials;
    correct += level.correct;
  }
  if (fit.total_trials == 0) {
    fit.unavailable = "no trials with an intensity and a scored response";
    return fit;
  }
  if (correct == fit.total_trials) {
    fit.unavailable = "slope not identifiable: all " + std::to_string(fit.total_trials) + " responses correct";
    return fit;
  }
  if (correct == 0) {
    fit.unavailable = "slope not identifiable: all " + std::to_string(fit.total_trials) + " responses incorrect";
    return fit;
  }
  if (levels.size() < 2) {
    fit.unavailable = "slope not identifiable: only one intensity level (" + std::to_string(fit.total_trials) + " trials)";
    return fit;
  }
  // Perfect separation: chance (or worse) up to some level and every answer right above it. The
  // likelihood then grows without bound as the slope steepens, so no finite slope is the ML estimate.
  for (std::size_t cut = 1; cut < levels.size(); ++cut) {
    bool separated = true;
    for (std::size_t i = 0; i < levels.size() && separated; ++i) {
      const double proportion = static_cast<double>(levels[i].correct) / static_cast<double>(levels[i].trials);
      separated = i < cut ? proportion <= options.guess_rate : levels[i].correct == levels[i].trials;
    }
    if (separated) {
      long above = 0;
      for (std::size_t i = cut; i < levels.size(); ++i) above += levels[i].trials;
      fit.unavailable = "slope not identifiable: all " + std::to_string(above) + " responses at intensity >= " +
                        shortest(levels[cut].intensity) + " correct, at or below chance below it (perfect separation)";
      return fit;
    }
  }
  const double x_min = levels.front().intensity;
  const double x_max = levels.back().intensity;
  if (options.shape == PsychometricShape::weibull && !(x_min > 0.0)) {
    fit.unavailable = "the Weibull function needs positive intensities (lowest is " + std::to_string(x_min) + ")";
    return fit;
  }
  const Bounds bounds = parameter_bounds(options.shape, x_min, x_max);
  Problem problem{&levels, options.shape, options.guess_rate};
  const double lapse_max = std::max(0.0, options.lapse_max);

  // Grid of starts: the likelihood can have several local optima when lapse and slope trade off.
  std::vector<double> best = {0.0, 0.0, 0.0};
  double best_value = INFINITY;
  for (int a = 0; a < 7; ++a) {
    for (int b = 0; b < 5; ++b) {
      const double alpha = x_min + (x_max - x_min) * (a + 0.5) / 7.0;
      const double log_beta = bounds.log_beta_low + (bounds.log_beta_high - bounds.log_beta_low) * (b + 1.0) / 6.0;
      const double lapse = lapse_max * 0.25;
      const double value = negative_log_likelihood(problem, alpha, std::exp(log_beta), lapse);
      if (value < best_value) {
        best_value = value;
        best = {alpha, log_beta, lapse};
      }
    }
  }
  nlopt::opt optimiser(nlopt::LN_BOBYQA, 3);
  // A fixed lapse (lapse_max = 0) is a zero-width bound, which BOBYQA accepts.
  optimiser.set_lower_bounds({bounds.alpha_low, bounds.log_beta_low, 0.0});
  optimiser.set_upper_bounds({bounds.alpha_high, bounds.log_beta_high, lapse_max});
  optimiser.set_min_objective(objective, &problem);
  optimiser.set_xtol_rel(1e-12);
  optimiser.set_ftol_abs(1e-13);
  optimiser.set_maxeval(5000);
  double value = best_value;
  try {
    optimiser.optimize(best, value);
  } catch (const nlopt::roundoff_limited&) {
    // The optimum is reached to rounding: `best` holds it.
  } catch (const std::exception& error) {
    fit.unavailable = std::string("the likelihood maximisation failed: ") + error.what();
    return fit;
  }
  fit.threshold = best[0];
  fit.slope = std::exp(best[1]);
  fit.lapse = best[2];
  fit.log_likelihood = -value;
  const double log_beta_range = bounds.log_beta_high - bounds.log_beta_low;
  if (best[1] > bounds.log_beta_high - 1e-3 * log_beta_range) {
    fit.unavailable = "slope not identifiable: the responses separate perfectly (the fit runs to the steepest slope allowed)";
    return fit;
  }
  if (best[0] <= bounds.alpha_low + 1e-9 * (bounds.alpha_high - bounds.alpha_low) ||
      best[0] >= bounds.alpha_high - 1e-9 * (bounds.alpha_high - bounds.alpha_low)) {
    fit.unavailable = "threshold not identifiable: it lies far outside the tested intensities";
    return fit;
  }
  for (const StimulusLevel& level : levels) {
    const double psi = std::clamp(fit.probability(level.intensity), kProbabilityFloor, 1.0 - kProbabilityFloor);
    const auto n = static_cast<double>(level.trials);
    const auto k = static_cast<double>(level.correct);
    fit.deviance += 2.0 * (deviance_term(k, n * psi) + deviance_term(n - k, n * (1.0 - psi)));
  }
  fit.deviance_df = static_cast<int>(levels.size()) - (lapse_max > 0.0 ? 3 : 2);
  return fit;
}

}  // namespace

std::string shape_name(PsychometricShape shape) {
  switch (shape) {
    case PsychometricShape::logistic: return "logistic";
    case PsychometricShape::cumulative_normal: return "cumulative normal";
    case PsychometricShape::weibull: return "Weibull";
  }
  return "unknown";
}

double psychometric_probability(PsychometricShape shape, double x, double alpha, double beta, double guess, double lapse) {
  double f = 0.0;
  switch (shape) {
    case PsychometricShape::logistic:
      f = 1.0 / (1.0 + std::exp(-beta * (x - alpha)));
      break;
    case PsychometricShape::cumulative_normal:
      f = boost::math::cdf(boost::math::normal_distribution<double>(), beta * (x - alpha));
      break;
    case PsychometricShape::weibull:
      f = x > 0.0 ? -std::expm1(-std::pow(x / alpha, beta)) : 0.0;
      break;
  }
  return guess + (1.0 - guess - lapse) * f;
}

double PsychometricFit::probability(double intensity) const {
  return psychometric_probability(shape, intensity, threshold, slope, guess, lapse);
}

std::vector<StimulusLevel> levels_from_trials(const std::vector<std::pair<double, bool>>& trials) {
  std::map<double, StimulusLevel> by_intensity;
  for (const auto& [intensity, correct] : trials) {
    StimulusLevel& level = by_intensity[intensity];
    level.intensity = intensity;
    ++level.trials;
    level.correct += correct ? 1 : 0;
  }
  std::vector<StimulusLevel> levels;
  for (const auto& entry : by_intensity) levels.push_back(entry.second);
  return levels;
}

PsychometricFit fit_psychometric(const std::vector<StimulusLevel>& levels, const PsychometricFitOptions& options) {
  PsychometricFit fit = fit_point(levels, options);
  if (!fit.ok() || options.bootstrap_samples <= 0) return fit;
  const CounterRandom random(options.seed, RandomStream::analysis_bootstrap);
  PsychometricFitOptions refit_options = options;
  refit_options.bootstrap_samples = 0;
  std::vector<double> thresholds;
  std::vector<double> slopes;
  std::vector<StimulusLevel> simulated = levels;
  for (int replicate = 0; replicate < options.bootstrap_samples; ++replicate) {
    for (std::size_t i = 0; i < levels.size(); ++i) {
      const double psi = fit.probability(levels[i].intensity);
      simulated[i].correct = 0;
      for (long t = 0; t < levels[i].trials; ++t) {
        const std::uint64_t index = (static_cast<std::uint64_t>(replicate) << 24) | i;
        simulated[i].correct += random.uniform(index, static_cast<std::uint32_t>(t)) < psi ? 1 : 0;
      }
    }
    const PsychometricFit refit = fit_point(simulated, refit_options);
    if (!refit.ok()) {
      ++fit.bootstrap_failures;
      continue;
    }
    thresholds.push_back(refit.threshold);
    slopes.push_back(refit.slope);
  }
  // Percentiles from fewer than 20 replicates would not reach the 2.5% tails at all.
  if (thresholds.size() >= 20) {
    fit.threshold_ci = percentile_interval(thresholds);
    fit.slope_ci = percentile_interval(slopes);
  }
  fit.bootstrap_thresholds = std::move(thresholds);
  return fit;
}

}  // namespace glarelab::analysis
