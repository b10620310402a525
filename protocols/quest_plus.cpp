// QUEST+ (Watson 2017) on explicit grids; see quest_plus.h for the steps and the conventions
// shared with the questplus package.
#include "protocols/quest_plus.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

namespace glarelab {
namespace {

// The cumulative normal as scipy.special.ndtr computes it (Cephes ndtr): erf near 0, erfc in
// the tails, so that small probabilities keep their relative precision.
double normal_cdf(double a) {
  const double x = a * 0.70710678118654752440;  // a / sqrt(2)
  const double z = std::abs(x);
  if (z < 0.70710678118654752440) return 0.5 + 0.5 * std::erf(x);
  const double y = 0.5 * std::erfc(z);
  return x > 0.0 ? 1.0 - y : y;
}

bool is_finite_grid(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

const char* role_name(ParameterRole role) {
  switch (role) {
    case ParameterRole::threshold: return "threshold";
    case ParameterRole::slope: return "slope";
    case ParameterRole::sd: return "sd";
    case ParameterRole::guess: return "guess";
    case ParameterRole::lapse: return "lapse";
    case ParameterRole::threshold_floor: return "threshold_floor";
    case ParameterRole::threshold_coefficient: return "threshold_coefficient";
  }
  return "threshold";
}

// Index of the first maximum (numpy argmax).
std::size_t first_maximum(const std::vector<double>& values) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < values.size(); ++i)
    if (values[i] > values[best]) best = i;
  return best;
}

}  // namespace

PsychometricShape parse_psychometric_shape(const std::string& name) {
  if (name == "weibull") return PsychometricShape::weibull;
  if (name == "logistic") return PsychometricShape::logistic;
  if (name == "normal") return PsychometricShape::normal;
  throw std::invalid_argument("unknown psychometric function '" + name + "' (choose 'weibull', 'logistic' or 'normal')");
}

StimulusScale parse_stimulus_scale(const std::string& name) {
  if (name == "db") return StimulusScale::db;
  if (name == "log10") return StimulusScale::log10;
  if (name == "linear") return StimulusScale::linear;
  throw std::invalid_argument("unknown stimulus scale '" + name + "' (choose 'db', 'log10' or 'linear')");
}

std::string to_string(PsychometricShape shape) {
  switch (shape) {
    case PsychometricShape::weibull: return "weibull";
    case PsychometricShape::logistic: return "logistic";
    case PsychometricShape::normal: return "normal";
  }
  return "weibull";
}

std::string to_string(StimulusScale scale) {
  switch (scale) {
    case StimulusScale::db: return "db";
    case StimulusScale::log10: return "log10";
    case StimulusScale::linear: return "linear";
  }
  return "db";
}

void validate_quest_plus_spec(const QuestPlusSpec& spec) {
  const std::string where = "QUEST+ '" + spec.name + "': ";
  if (spec.stimulus.empty()) throw std::invalid_argument(where + "needs at least one stimulus dimension");
  std::set<std::string> names;
  for (const StimulusDimension& d : spec.stimulus) {
    if (d.values.empty()) throw std::invalid_argument(where + "stimulus dimension '" + d.name + "' has no grid values");
    if (!is_finite_grid(d.values))
      throw std::invalid_argument(where + "stimulus dimension '" + d.name + "' has a value that is not finite");
    if (!names.insert(d.name).second) throw std::invalid_argument(where + "duplicate name '" + d.name + "'");
  }
  std::set<ParameterRole> roles;
  std::set<std::size_t> coefficient_dimensions;
  for (const ParameterAxis& a : spec.parameters) {
    const std::string axis = "parameter '" + a.name + "'";
    if (!names.insert(a.name).second) throw std::invalid_argument(where + "duplicate name '" + a.name + "'");
    if (a.values.empty()) throw std::invalid_argument(where + axis + " has no grid values");
    if (!is_finite_grid(a.values)) throw std::invalid_argument(where + axis + " has a value that is not finite");
    if (a.role == ParameterRole::threshold_coefficient) {
      if (a.stimulus_dimension < 1 || a.stimulus_dimension >= spec.stimulus.size())
        throw std::invalid_argument(where + axis + ": a threshold coefficient must multiply a stimulus dimension after the first");
      if (!coefficient_dimensions.insert(a.stimulus_dimension).second)
        throw std::invalid_argument(where + axis + ": two threshold coefficients for stimulus dimension '" +
                                    spec.stimulus[a.stimulus_dimension].name + "'");
    } else if (!roles.insert(a.role).second) {
      throw std::invalid_argument(where + "two parameters with the role " + role_name(a.role));
    }
    if (!a.prior.empty()) {
      if (a.prior.size() != a.values.size())
        throw std::invalid_argument(where + axis + " prior has " + std::to_string(a.prior.size()) +
                                    " weights for " + std::to_string(a.values.size()) + " grid values");
      double total = 0.0;
      for (double w : a.prior) {
        if (!(w >= 0.0) || !std::isfinite(w))
          throw std::invalid_argument(where + axis + " prior weights must be finite and >= 0");
        total += w;
      }
      if (!(total > 0.0)) throw std::invalid_argument(where + axis + " prior weights are all zero");
    }
    if (a.role == ParameterRole::lapse || a.role == ParameterRole::guess) {
      for (double v : a.values)
        if (!(v >= 0.0 && v < 1.0))
          throw std::invalid_argument(where + axis + " values must lie in [0, 1)");
    }
    if (a.role == ParameterRole::sd || a.role == ParameterRole::slope) {
      for (double v : a.values)
        if (!(v > 0.0)) throw std::invalid_argument(where + axis + " values must be > 0");
    }
  }
  if (roles.count(ParameterRole::threshold) == 0) throw std::invalid_argument(where + "needs a threshold parameter");
  const bool normal = spec.shape == PsychometricShape::normal;
  if (normal && roles.count(ParameterRole::sd) == 0)
    throw std::invalid_argument(where + "the normal function needs an sd parameter");
  if (normal && roles.count(ParameterRole::slope) != 0)
    throw std::invalid_argument(where + "the normal function takes sd, not slope");
  if (!normal && roles.count(ParameterRole::slope) == 0)
    throw std::invalid_argument(where + "the " + to_string(spec.shape) + " function needs a slope parameter");
  if (!normal && roles.count(ParameterRole::sd) != 0)
    throw std::invalid_argument(where + "only the normal function takes sd");
  if (roles.count(ParameterRole::lapse) == 0) throw std::invalid_argument(where + "needs a lapse parameter");
  if (spec.guess_equals_lapse && roles.count(ParameterRole::guess) != 0)
    throw std::invalid_argument(where + "guess_equals_lapse leaves no guess parameter");
  if (!spec.guess_equals_lapse && roles.count(ParameterRole::guess) == 0 &&
      !(spec.fixed_guess >= 0.0 && spec.fixed_guess < 1.0))
    throw std::invalid_argument(where + "guess must lie in [0, 1)");
  // Every guess + lapse combination must leave room for the function: guess + lapse < 1.
  double max_guess = spec.fixed_guess, max_lapse = 0.0;
  for (const ParameterAxis& a : spec.parameters) {
    if (a.role == ParameterRole::guess) max_guess = *std::max_element(a.values.begin(), a.values.end());
    if (a.role == ParameterRole::lapse) max_lapse = *std::max_element(a.values.begin(), a.values.end());
  }
  if (spec.guess_equals_lapse) max_guess = max_lapse;
  if (!(max_guess + max_lapse < 1.0)) throw std::invalid_argument(where + "guess + lapse must be < 1");
  if (spec.shape == PsychometricShape::weibull && spec.scale == StimulusScale::linear) {
    for (const ParameterAxis& a : spec.parameters)
      if (a.role == ParameterRole::threshold || a.role == ParameterRole::threshold_floor)
        for (double v : a.values)
          if (!(v > 0.0)) throw std::invalid_argument(where + "a Weibull on a linear scale needs thresholds > 0");
    for (double v : spec.stimulus.front().values)
      if (!(v >= 0.0)) throw std::invalid_argument(where + "a Weibull on a linear scale needs intensities >= 0");
  }
  if (spec.max_trials < 1) throw std::invalid_argument(where + "max_trials must be >= 1");
  if (spec.min_trials < 0 || spec.min_trials > spec.max_trials)
    throw std::invalid_argument(where + "min_trials must lie between 0 and max_trials");
  if (spec.stop_sd) {
    if (!(*spec.stop_sd > 0.0) || !std::isfinite(*spec.stop_sd))
      throw std::invalid_argument(where + "stop_sd must be > 0");
    const bool found = std::any_of(spec.parameters.begin(), spec.parameters.end(),
                                   [&](const ParameterAxis& a) { return a.name == spec.stop_sd_parameter; });
    if (!found) throw std::invalid_argument(where + "stop_sd names no parameter '" + spec.stop_sd_parameter + "'");
  }
  // The grids' product must fit in memory: stimulus points x parameter points doubles.
  double cells = 1.0;
  for (const StimulusDimension& d : spec.stimulus) cells *= static_cast<double>(d.values.size());
  for (const ParameterAxis& a : spec.parameters) cells *= static_cast<double>(a.values.size());
  if (cells > 5e7)
    throw std::invalid_argument(where + "stimulus x parameter grid has " + std::to_string(static_cast<long long>(cells)) +
                                " points, more than 5e7");
}

double quest_plus_probability_correct(const QuestPlusSpec& spec, const std::vector<double>& stimulus,
                                      const std::vector<double>& parameters) {
  double t = 0.0, spread = 1.0, guess = spec.fixed_guess, lapse = 0.0;
  std::optional<double> floor;
  for (std::size_t i = 0; i < spec.parameters.size(); ++i) {
    const double v = parameters[i];
    switch (spec.parameters[i].role) {
      case ParameterRole::threshold: t = v; break;
      case ParameterRole::slope:
      case ParameterRole::sd: spread = v; break;
      case ParameterRole::guess: guess = v; break;
      case ParameterRole::lapse: lapse = v; break;
      case ParameterRole::threshold_floor: floor = v; break;
      case ParameterRole::threshold_coefficient: break;
    }
  }
  // Threshold model: intercept + c_1 x_1 + ..., added left to right in the parameters' order (as
  // questplus's csf adds c0 + cf f + cw w), then floored.
  for (std::size_t i = 0; i < spec.parameters.size(); ++i) {
    const ParameterAxis& a = spec.parameters[i];
    if (a.role == ParameterRole::threshold_coefficient) t = t + parameters[i] * stimulus[a.stimulus_dimension];
  }
  if (floor) t = std::max(*floor, t);
  if (spec.guess_equals_lapse) guess = lapse;
  const double x = stimulus.front();
  switch (spec.shape) {
    case PsychometricShape::weibull: {
      double e = 0.0;
      switch (spec.scale) {
        case StimulusScale::db: e = std::pow(10.0, spread * (x - t) / 20.0); break;
        case StimulusScale::log10: e = std::pow(10.0, spread * (x - t)); break;
        case StimulusScale::linear: e = std::pow(x / t, spread); break;
      }
      return 1.0 - lapse - (1.0 - guess - lapse) * std::exp(-e);
    }
    case PsychometricShape::logistic:
      return guess + (1.0 - guess - lapse) / (1.0 + std::exp(-spread * (x - t)));
    case PsychometricShape::normal:
      if (spec.guess_equals_lapse) return lapse + (1.0 - 2.0 * lapse) * normal_cdf((x - t) / spread);
      return guess + (1.0 - guess - lapse) * normal_cdf((x - t) / spread);
  }
  return 0.0;
}

QuestPlus::QuestPlus(QuestPlusSpec spec) : spec_(std::move(spec)) {
  validate_quest_plus_spec(spec_);
  stimulus_count_ = 1;
  for (const StimulusDimension& d : spec_.stimulus) stimulus_count_ *= d.values.size();
  parameter_count_ = 1;
  for (const ParameterAxis& a : spec_.parameters) parameter_count_ *= a.values.size();

  // The prior P0(s): the product of the per-parameter weights (1 where none are given),
  // normalised to sum to 1.
  prior_.assign(parameter_count_, 1.0);
  for (std::size_t p = 0; p < parameter_count_; ++p) {
    std::size_t rest = p;
    double w = 1.0;
    for (std::size_t a = spec_.parameters.size(); a-- > 0;) {
      const ParameterAxis& axis = spec_.parameters[a];
      const std::size_t i = rest % axis.values.size();
      rest /= axis.values.size();
      if (!axis.prior.empty()) w *= axis.prior[i];
    }
    prior_[p] = w;
  }
  double total = 0.0;
  for (double w : prior_) total += w;
  if (!(total > 0.0)) throw std::invalid_argument("QUEST+ '" + spec_.name + "': the prior is zero everywhere");
  for (double& w : prior_) w /= total;
  posterior_ = prior_;

  // Q(x, s) at every stimulus and parameter point.
  p_correct_.resize(stimulus_count_ * parameter_count_);
  for (std::size_t s = 0; s < stimulus_count_; ++s) {
    const std::vector<double> x = stimulus_at(s);
    for (std::size_t p = 0; p < parameter_count_; ++p)
      p_correct_[s * parameter_count_ + p] = quest_plus_probability_correct(spec_, x, parameters_at(p));
  }
  choose_next();
}

std::vector<double> QuestPlus::stimulus_at(std::size_t index) const {
  if (index >= stimulus_count_) throw std::out_of_range("QUEST+: stimulus index out of range");
  std::vector<double> x(spec_.stimulus.size());
  for (std::size_t d = spec_.stimulus.size(); d-- > 0;) {
    const std::vector<double>& values = spec_.stimulus[d].values;
    x[d] = values[index % values.size()];
    index /= values.size();
  }
  return x;
}

std::vector<double> QuestPlus::parameters_at(std::size_t index) const {
  if (index >= parameter_count_) throw std::out_of_range("QUEST+: parameter index out of range");
  std::vector<double> s(spec_.parameters.size());
  for (std::size_t a = spec_.parameters.size(); a-- > 0;) {
    const std::vector<double>& values = spec_.parameters[a].values;
    s[a] = values[index % values.size()];
    index /= values.size();
  }
  return s;
}

std::vector<double> QuestPlus::expected_entropies() const {
  std::vector<double> expected(stimulus_count_);
  std::vector<double> joint(parameter_count_);
  for (std::size_t s = 0; s < stimulus_count_; ++s) {
    const double* q = &p_correct_[s * parameter_count_];
    double e = 0.0;
    for (int outcome = 0; outcome < 2; ++outcome) {
      // P(r | x) = sum_s P_k(s) Psi(x, s)_r, then H(x, r) of the posterior P_k(s) Psi(x, s)_r / P(r | x);
      // 0 log 0 counts as 0 (questplus: NaN skipped by the sum).
      double pk = 0.0;
      for (std::size_t p = 0; p < parameter_count_; ++p) {
        joint[p] = posterior_[p] * (outcome == 0 ? q[p] : 1.0 - q[p]);
        pk += joint[p];
      }
      if (!(pk > 0.0)) continue;  // an impossible outcome adds nothing to E(x)
      double h = 0.0;
      for (std::size_t p = 0; p < parameter_count_; ++p) {
        const double v = joint[p] / pk;
        if (v > 0.0) h += v * std::log(v);
      }
      // E(x) = sum_r H(x, r) P(r | x)
      e += pk * -h;
    }
    expected[s] = e;
  }
  return expected;
}

void QuestPlus::choose_next() {
  const std::vector<double> expected = expected_entropies();
  // argmin_x E(x), the first grid point of equal minima (numpy argmin).
  std::size_t best = 0;
  for (std::size_t s = 1; s < stimulus_count_; ++s)
    if (expected[s] < expected[best]) best = s;
  next_index_ = best;
  next_entropy_ = expected[best];
  next_stimulus_ = stimulus_at(best);
}

void QuestPlus::add_response(std::size_t stimulus_index, bool correct) {
  if (stimulus_index >= stimulus_count_) throw std::out_of_range("QUEST+: stimulus index out of range");
  // P_k+1(s) = P_k(s) Psi(x, s)_r / sum over s of the same.
  const double* q = &p_correct_[stimulus_index * parameter_count_];
  double total = 0.0;
  for (std::size_t p = 0; p < parameter_count_; ++p) {
    posterior_[p] *= correct ? q[p] : 1.0 - q[p];
    total += posterior_[p];
  }
  if (!(total > 0.0))
    throw std::domain_error("QUEST+ '" + spec_.name + "': the response has probability 0 under every parameter point");
  for (double& v : posterior_) v /= total;
  stimuli_.push_back(stimulus_index);
  responses_.push_back(correct);
  choose_next();
}

std::vector<double> QuestPlus::marginal(std::size_t parameter) const {
  const std::vector<double>& values = spec_.parameters.at(parameter).values;
  std::size_t inner = 1;
  for (std::size_t a = parameter + 1; a < spec_.parameters.size(); ++a) inner *= spec_.parameters[a].values.size();
  std::vector<double> m(values.size(), 0.0);
  for (std::size_t p = 0; p < parameter_count_; ++p) m[(p / inner) % values.size()] += posterior_[p];
  return m;
}

std::vector<ParameterSummary> QuestPlus::summary() const {
  const std::vector<double> mode = parameters_at(first_maximum(posterior_));
  std::vector<ParameterSummary> out;
  for (std::size_t a = 0; a < spec_.parameters.size(); ++a) {
    const std::vector<double>& values = spec_.parameters[a].values;
    if (values.size() == 1) {  // a fixed value: exactly itself, SD 0 (no rounding residue)
      out.push_back({spec_.parameters[a].name, values[0], values[0], 0.0});
      continue;
    }
    const std::vector<double> m = marginal(a);
    double mean = 0.0;
    for (std::size_t i = 0; i < values.size(); ++i) mean += m[i] * values[i];
    double variance = 0.0;
    for (std::size_t i = 0; i < values.size(); ++i) variance += m[i] * (values[i] - mean) * (values[i] - mean);
    out.push_back({spec_.parameters[a].name, mode[a], mean, std::sqrt(variance)});
  }
  return out;
}

double QuestPlus::entropy() const {
  double h = 0.0;
  for (double v : posterior_)
    if (v > 0.0) h -= v * std::log(v);
  return h;
}

bool QuestPlus::finished() const {
  if (trial_count() >= spec_.max_trials) return true;
  if (!spec_.stop_sd || trial_count() < spec_.min_trials) return false;
  for (const ParameterSummary& s : summary())
    if (s.name == spec_.stop_sd_parameter) return s.sd <= *spec_.stop_sd;
  return false;
}

std::vector<double> psi_default_slopes() {
  // Palamedes PAL_AMPM_setupPM: priorBetaRange = -1:.05:1 (log10 slope), 41 values.
  std::vector<double> slopes;
  for (int i = -20; i <= 20; ++i) slopes.push_back(std::pow(10.0, i * 0.05));
  return slopes;
}

QuestPlusSpec make_psi_spec(std::vector<double> intensities, std::vector<double> thresholds, double guess) {
  QuestPlusSpec spec;
  spec.name = "psi";
  spec.shape = PsychometricShape::weibull;
  spec.scale = StimulusScale::log10;
  spec.stimulus = {{"intensity", std::move(intensities)}};
  spec.parameters = {{"threshold", ParameterRole::threshold, std::move(thresholds), {}, 0},
                     {"slope", ParameterRole::slope, psi_default_slopes(), {}, 0},
                     {"lapse", ParameterRole::lapse, {0.02}, {}, 0}};
  spec.fixed_guess = guess;
  return spec;
}

}  // namespace glarelab
