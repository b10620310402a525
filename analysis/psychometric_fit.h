#pragma once
// Maximum-likelihood psychometric function fits (Wichmann & Hill 2001, "The psychometric
// function: I. Fitting, sampling, and goodness of fit", Eq. 1):
//   psi(x) = gamma + (1 - gamma - lambda) F(x; alpha, beta)
// with the guess rate gamma fixed by the task (1/m for m-alternative forced choice), the lapse
// rate lambda free within [0, lapse_max] (Wichmann & Hill recommend [0, 0.06]), and F one of
//   logistic:          F = 1 / (1 + exp(-beta (x - alpha)))
//   cumulative normal: F = Phi(beta (x - alpha))
//   Weibull:           F = 1 - exp(-(x / alpha)^beta), x > 0
// so alpha is the threshold (F = 1/2 for logistic and normal, F = 1 - 1/e for Weibull) and beta
// the slope parameter. The likelihood is maximised with NLopt's bounded BOBYQA from a grid of
// starts. Parametric bootstrap (Wichmann & Hill 2001b): simulate each level from the fitted
// psi with the observed numbers of trials, refit, take the 2.5 and 97.5 percentiles.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace glarelab::analysis {

enum class PsychometricShape { logistic, cumulative_normal, weibull };
std::string shape_name(PsychometricShape shape);

struct StimulusLevel {
  double intensity = 0.0;
  long trials = 0;
  long correct = 0;
};

struct PsychometricFitOptions {
  PsychometricShape shape = PsychometricShape::logistic;
  double guess_rate = 0.5;
  double lapse_max = 0.06;  // 0 fixes the lapse rate at 0
  int bootstrap_samples = 200;  // 0: no intervals
  std::uint64_t seed = 1;  // bootstrap draws: CounterRandom(seed, RandomStream::analysis_bootstrap)
};

struct Interval {
  double low = 0.0;
  double high = 0.0;
};

struct PsychometricFit {
  std::string unavailable;  // non-empty: why no fit ("slope not identifiable: ...")
  PsychometricShape shape = PsychometricShape::logistic;
  double threshold = 0.0;  // alpha
  double slope = 0.0;      // beta
  double lapse = 0.0;      // lambda
  double guess = 0.5;      // gamma (fixed)
  double deviance = 0.0;   // 2 * log likelihood ratio against the saturated model
  int deviance_df = 0;     // levels - free parameters
  double log_likelihood = 0.0;
  std::optional<Interval> threshold_ci;  // 95% parametric bootstrap
  std::optional<Interval> slope_ci;
  int bootstrap_failures = 0;  // replicates whose refit was not identifiable (left out)
  std::vector<double> bootstrap_thresholds;  // the identifiable replicates' thresholds, in replicate order
  long total_trials = 0;
  bool ok() const { return unavailable.empty(); }
  double probability(double intensity) const;  // psi(x) with the fitted parameters
};

// The 2.5 and 97.5 percentiles (linear interpolation between order statistics); values not empty.
Interval percentile_interval(std::vector<double> values);

// Proportion correct psi(x) for the given parameters.
double psychometric_probability(PsychometricShape shape, double x, double alpha, double beta, double guess,
                                double lapse);

// Groups (intensity, correct) trials into levels sorted by intensity.
std::vector<StimulusLevel> levels_from_trials(const std::vector<std::pair<double, bool>>& trials);

PsychometricFit fit_psychometric(const std::vector<StimulusLevel>& levels, const PsychometricFitOptions& options);

}  // namespace glarelab::analysis
