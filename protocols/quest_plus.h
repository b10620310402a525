#pragma once
// QUEST+ (Watson 2017, "QUEST+: A general multidimensional Bayesian adaptive psychometric
// method", Journal of Vision 17(3):10): a posterior over a grid of psychometric parameters,
// updated by Bayes' rule after each trial, and each next stimulus the point of a stimulus grid
// that minimises the expected entropy of the posterior after the trial. Psi (Kontsevich & Tyler
// 1999) is the case of one stimulus dimension and a threshold x slope grid (make_psi_spec).
//
// Notation of Watson 2017: stimulus x (a point of the stimulus grid, any number of dimensions),
// parameters s (a point of the parameter grid), outcome r (here two: correct, incorrect),
// psychometric function Psi(x, s), whose correct component is written Q(x, s) below. The
// paper's steps, which the comments below name: the prior P0(s); the
// posterior after each trial, P_k+1(s) = P_k(s) Psi(x_k, s)_r_k normalised; for each candidate x
// and outcome r the probability P(r | x) = sum_s P_k(s) Psi(x, s)_r and the entropy H(x, r) of
// the posterior that outcome would give; the expected entropy E(x) = sum_r H(x, r) P(r | x);
// the next stimulus argmin_x E(x).
//
// The computation is that of the questplus package (hoechenberger/questplus, qp.py) that
// reproduces Watson's examples, so the chosen stimuli can be compared one for one
// (tests/quest_plus_test.cpp):
// - grids are flattened in C order (first stimulus dimension / first parameter outermost);
// - the prior is uniform or the product of one weight vector per parameter, normalised;
// - the next stimulus minimises expected entropy; ties go to the first grid point in the
//   flattened order (numpy argmin);
// - the estimate "mode" is the parameter point of the joint posterior maximum, ties to the first.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace glarelab {

// The psychometric function's shape F (Watson 2017, "Psychometric functions"), with guess gamma
// and lapse delta: Q = gamma + (1 - gamma - delta) F.
//   weibull:  F = 1 - exp(-10^(beta (x - t) / 20))   scale db (Watson's examples: x, t in dB)
//             F = 1 - exp(-10^(beta (x - t)))        scale log10
//             F = 1 - exp(-(x / t)^beta)             scale linear
//   logistic: F = 1 / (1 + exp(-beta (x - t)))
//   normal:   F = Phi((x - t) / sd)                  (cumulative normal, mean t, SD sd)
// The Weibull is evaluated as questplus writes it: Q = 1 - delta - (1 - gamma - delta) exp(...).
enum class PsychometricShape { weibull, logistic, normal };
enum class StimulusScale { db, log10, linear };

PsychometricShape parse_psychometric_shape(const std::string& name);  // std::invalid_argument otherwise
StimulusScale parse_stimulus_scale(const std::string& name);          // "db" | "log10" | "linear"
std::string to_string(PsychometricShape shape);
std::string to_string(StimulusScale scale);

// What a parameter axis is in the psychometric function.
//   threshold: t (with more stimulus dimensions, the intercept of the threshold model below);
//   slope: beta (weibull, logistic); sd: the normal's SD;
//   guess: gamma; lapse: delta;
//   threshold_floor: the lowest threshold of the threshold model;
//   threshold_coefficient: the change of threshold per unit of one further stimulus dimension.
// With stimulus dimensions x_0 (the intensity the function runs over) and x_1 .. x_n, the
// threshold at a stimulus is max(threshold_floor, threshold + c_1 x_1 + ... + c_n x_n)
// (Watson 2017, Example 4, the contrast sensitivity function: t = max(t_min, c0 + cf f + cw w)).
enum class ParameterRole { threshold, slope, sd, guess, lapse, threshold_floor, threshold_coefficient };

struct StimulusDimension {
  std::string name;
  std::vector<double> values;  // grid points, in the order ties are broken
};

struct ParameterAxis {
  std::string name;
  ParameterRole role = ParameterRole::threshold;
  std::vector<double> values;   // grid points
  std::vector<double> prior;    // empty: uniform; else one non-negative weight per value
  std::size_t stimulus_dimension = 0;  // threshold_coefficient: which dimension (>= 1) it multiplies
};

struct QuestPlusSpec {
  std::string name = "quest_plus";
  // The first dimension is the intensity the psychometric function runs over.
  std::vector<StimulusDimension> stimulus;
  std::vector<ParameterAxis> parameters;  // flattened in this order
  PsychometricShape shape = PsychometricShape::weibull;
  StimulusScale scale = StimulusScale::db;  // weibull only
  // When no guess axis is given: the guess rate is fixed (1 / alternatives in forced choice) or,
  // with guess_equals_lapse, equal to the lapse (Watson 2017, Example 3: a symmetric function
  // delta + (1 - 2 delta) F).
  double fixed_guess = 0.5;
  bool guess_equals_lapse = false;
  // Stopping: after max_trials, or once the posterior SD of `stop_sd_parameter` is at most
  // `stop_sd` (in that parameter's units) after at least min_trials.
  int max_trials = 40;
  int min_trials = 0;
  std::optional<double> stop_sd;
  std::string stop_sd_parameter = "threshold";
};

// std::invalid_argument naming the rule broken: no stimulus dimension or an empty grid, a grid
// value that is not finite, duplicate names, a missing threshold or slope (sd for normal), roles
// given twice, priors of the wrong length, negative or all-zero priors, guess/lapse outside
// [0, 1) or summing to 1 or more, a coefficient for a dimension that does not exist, Weibull with
// a linear scale at a non-positive threshold, max_trials < 1, min_trials > max_trials, stop_sd <= 0
// or naming no parameter.
void validate_quest_plus_spec(const QuestPlusSpec& spec);

// Q(x, s): the probability of a correct response, the correct component of Watson's Psi(x, s).
// `stimulus` holds one value per stimulus dimension, `parameters` one per parameter axis.
double quest_plus_probability_correct(const QuestPlusSpec& spec, const std::vector<double>& stimulus,
                                      const std::vector<double>& parameters);

// Posterior summary of one parameter.
struct ParameterSummary {
  std::string name;
  double mode = 0.0;  // its value at the joint posterior maximum
  double mean = 0.0;  // marginal posterior mean
  double sd = 0.0;    // marginal posterior SD
};

class QuestPlus {
 public:
  explicit QuestPlus(QuestPlusSpec spec);

  const QuestPlusSpec& spec() const { return spec_; }
  std::size_t stimulus_count() const { return stimulus_count_; }
  std::size_t parameter_count() const { return parameter_count_; }

  // The stimulus of the next trial (one value per dimension) and its grid index.
  const std::vector<double>& next_stimulus() const { return next_stimulus_; }
  std::size_t next_stimulus_index() const { return next_index_; }
  // The expected posterior entropy E(x) (nats) at the next stimulus.
  double next_expected_entropy() const { return next_entropy_; }
  // E(x) at every stimulus grid point for the current posterior.
  std::vector<double> expected_entropies() const;

  // Bayes' rule, P_k+1(s) = P_k(s) Psi(x, s)_r normalised, at a stimulus grid point, then the
  // next stimulus. Throws std::out_of_range for an index outside the grid.
  void add_response(std::size_t stimulus_index, bool correct);
  void add_response(bool correct) { add_response(next_index_, correct); }

  int trial_count() const { return static_cast<int>(responses_.size()); }
  bool finished() const;

  const std::vector<double>& posterior() const { return posterior_; }  // flattened, sums to 1
  const std::vector<double>& prior() const { return prior_; }
  std::vector<ParameterSummary> summary() const;
  std::vector<double> marginal(std::size_t parameter) const;
  // Entropy of the posterior (nats).
  double entropy() const;
  // Stimulus values of a grid index; parameter values of a flattened parameter index.
  std::vector<double> stimulus_at(std::size_t index) const;
  std::vector<double> parameters_at(std::size_t index) const;
  // Probability of a correct response at stimulus grid point s for flattened parameter point p.
  double likelihood_correct(std::size_t s, std::size_t p) const { return p_correct_[s * parameter_count_ + p]; }

  const std::vector<std::size_t>& stimulus_indices() const { return stimuli_; }
  const std::vector<bool>& responses() const { return responses_; }

 private:
  void choose_next();

  QuestPlusSpec spec_;
  std::size_t stimulus_count_ = 0;
  std::size_t parameter_count_ = 0;
  std::vector<double> p_correct_;  // [stimulus][parameter], flattened
  std::vector<double> prior_;
  std::vector<double> posterior_;
  std::vector<double> next_stimulus_;
  std::size_t next_index_ = 0;
  double next_entropy_ = 0.0;
  std::vector<std::size_t> stimuli_;
  std::vector<bool> responses_;
};

// Psi (Kontsevich & Tyler 1999, "Bayesian adaptive estimation of psychometric slope and
// threshold", Vision Research 39, 2729-2737) with the defaults of Palamedes' PAL_AMPM_setupPM:
// a Weibull on a log10 intensity axis (Palamedes' Gumbel), slopes 10^(-1 : 0.05 : 1), guess
// 1 / alternatives, lapse 0.02, uniform prior. `intensities` and `thresholds` in log10 units.
QuestPlusSpec make_psi_spec(std::vector<double> intensities, std::vector<double> thresholds, double guess);
std::vector<double> psi_default_slopes();

}  // namespace glarelab
