// QUEST, transcribed from Psychtoolbox's Quest*.m functions (see quest.h). Index arithmetic is
// 0-based here; rounding of intensities to the grid is MATLAB's round (half away from zero).
#include "protocols/quest.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace glarelab {
namespace {

// Linear interpolation in a table sorted by increasing xs, clamping outside it (MATLAB interp1
// inside the table; numpy.interp at the ends, as PsychoPy's port does).
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double at) {
  if (at <= xs.front()) return ys.front();
  if (at >= xs.back()) return ys.back();
  const auto upper = std::upper_bound(xs.begin(), xs.end(), at);
  const auto k = static_cast<std::size_t>(upper - xs.begin());
  const double f = (at - xs[k - 1]) / (xs[k] - xs[k - 1]);
  return ys[k - 1] + f * (ys[k] - ys[k - 1]);
}

double weibull(const QuestSpec& s, double x) {
  return s.delta * s.gamma + (1.0 - s.delta) * (1.0 - (1.0 - s.gamma) * std::exp(-std::pow(10.0, s.beta * x)));
}

}  // namespace

QuestPlacement parse_quest_placement(const std::string& name) {
  if (name == "quantile") return QuestPlacement::quantile;
  if (name == "mean") return QuestPlacement::mean;
  if (name == "mode") return QuestPlacement::mode;
  throw std::invalid_argument("unknown QUEST placement '" + name + "' (choose 'quantile', 'mean' or 'mode')");
}

std::string to_string(QuestPlacement placement) {
  switch (placement) {
    case QuestPlacement::quantile: return "quantile";
    case QuestPlacement::mean: return "mean";
    case QuestPlacement::mode: return "mode";
  }
  return "quantile";
}

void validate_quest_spec(const QuestSpec& s) {
  const std::string where = "QUEST '" + s.name + "': ";
  if (!(s.t_guess_sd > 0.0)) throw std::invalid_argument(where + "t_guess_sd must be > 0");
  if (!(s.grain > 0.0)) throw std::invalid_argument(where + "grain must be > 0");
  if (!(s.range > s.grain)) throw std::invalid_argument(where + "range must exceed grain");
  if (!(s.range / s.grain <= 1e6)) throw std::invalid_argument(where + "range / grain must be <= 1e6 grid points");
  if (!(s.beta > 0.0)) throw std::invalid_argument(where + "beta must be > 0");
  if (!(s.gamma > 0.0 && s.gamma < 1.0)) throw std::invalid_argument(where + "gamma must lie in (0, 1)");
  if (!(s.delta >= 0.0 && s.delta < 1.0)) throw std::invalid_argument(where + "delta must lie in [0, 1)");
  if (!(s.p_threshold > s.gamma && s.p_threshold < 1.0))
    throw std::invalid_argument(where + "p_threshold must lie between gamma and 1");
  if (s.quantile_order && !(*s.quantile_order > 0.0 && *s.quantile_order < 1.0))
    throw std::invalid_argument(where + "quantile_order must lie in (0, 1)");
  if (s.n_trials < 1) throw std::invalid_argument(where + "n_trials must be >= 1");
  if (s.min_value && s.max_value && *s.min_value > *s.max_value)
    throw std::invalid_argument(where + "min_value is above max_value");
}

Quest::Quest(QuestSpec spec) : spec_(std::move(spec)) {
  validate_quest_spec(spec_);
  const QuestSpec& s = spec_;
  // QuestCreate: dim = range / grain rounded up to an even integer.
  dim_ = 2 * static_cast<int>(std::ceil(s.range / s.grain / 2.0));

  // QuestRecompute: Gaussian prior on the grid.
  double sum = 0.0;
  for (int i = -dim_ / 2; i <= dim_ / 2; ++i) {
    const double x = i * s.grain;
    x_.push_back(x);
    pdf_.push_back(std::exp(-0.5 * (x / s.t_guess_sd) * (x / s.t_guess_sd)));
    sum += pdf_.back();
  }
  for (double& p : pdf_) p /= sum;

  // The unshifted Weibull on the doubled grid, and x_threshold from its strictly monotonic part.
  std::vector<double> x2;
  for (int i = -dim_; i <= dim_; ++i) {
    x2.push_back(i * s.grain);
    p2_.push_back(weibull(s, x2.back()));
  }
  if (p2_.front() >= s.p_threshold || p2_.back() <= s.p_threshold)
    throw std::invalid_argument("QUEST '" + s.name + "': the psychometric function's range on the grid omits p_threshold");
  std::vector<double> p_mono, x_mono;
  for (std::size_t k = 0; k + 1 < p2_.size(); ++k) {
    if (p2_[k + 1] != p2_[k]) {
      p_mono.push_back(p2_[k]);
      x_mono.push_back(x2[k]);
    }
  }
  if (p_mono.size() < 2) throw std::invalid_argument("QUEST '" + s.name + "': the psychometric function is flat");
  x_threshold_ = interpolate(p_mono, x_mono, s.p_threshold);
  for (std::size_t k = 0; k < p2_.size(); ++k) p2_[k] = weibull(s, x2[k] + x_threshold_);

  // King-Smith, Grigsby, Vingrys, Benes & Supowit (1994), "Efficient and unbiased modifications of
  // the QUEST threshold method", Vision Research 34(7): the most informative quantile order, as
  // QuestRecompute computes it.
  constexpr double kEps = 1e-14;
  const double pl = p2_.front();
  const double ph = p2_.back();
  double pe = ph * std::log(ph + kEps) - pl * std::log(pl + kEps) + (1.0 - ph + kEps) * std::log(1.0 - ph + kEps) -
              (1.0 - pl + kEps) * std::log(1.0 - pl + kEps);
  pe = 1.0 / (1.0 + std::exp(pe / (pl - ph)));
  quantile_order_ = s.quantile_order.value_or((pe - pl) / (ph - pl));
  next_intensity_ = s.t_guess;
  if (s.min_value) next_intensity_ = std::max(next_intensity_, *s.min_value);
  if (s.max_value) next_intensity_ = std::min(next_intensity_, *s.max_value);
}

void Quest::add_response(double intensity, bool correct) {
  // QuestUpdate: pdf(k) *= s2(response, ii(k)), s2 = fliplr([1 - p2; p2]), so that the factor is
  // p2 or 1 - p2 at x2 index 3 dim / 2 - k + r (ii(k) = dim / 2 + k - r), i.e. at x = (intensity on the grid) - t_k.
  const double finite = std::clamp(intensity, -1e10, 1e10);
  const double r = std::round((finite - spec_.t_guess) / spec_.grain);
  const auto n2 = static_cast<long long>(p2_.size());
  long long first = static_cast<long long>(dim_) / 2 - static_cast<long long>(r);  // ii(0), before clamping
  const long long last = first + dim_;
  // Out of the table: QuestUpdate shifts the whole index range back inside (the pdf becomes
  // inexact there, as Psychtoolbox warns).
  if (first < 0) first = 0;
  else if (last > n2 - 1) first = n2 - 1 - dim_;
  double sum = 0.0;
  for (std::size_t k = 0; k < pdf_.size(); ++k) {
    const auto j = static_cast<std::size_t>(first + static_cast<long long>(k));  // index into s2
    const double p = p2_[p2_.size() - 1 - j];
    pdf_[k] *= correct ? p : 1.0 - p;
    sum += pdf_[k];
  }
  if (!(sum > 0.0)) throw std::runtime_error("QUEST '" + spec_.name + "': the posterior vanished");
  for (double& p : pdf_) p /= sum;  // normalising changes no statistic and prevents underflow
  intensities_.push_back(intensity);
  responses_.push_back(correct);
  next_intensity_ = placement_value();
  if (spec_.min_value) next_intensity_ = std::max(next_intensity_, *spec_.min_value);
  if (spec_.max_value) next_intensity_ = std::min(next_intensity_, *spec_.max_value);
}

double Quest::placement_value() const {
  switch (spec_.placement) {
    case QuestPlacement::quantile: return quantile();
    case QuestPlacement::mean: return mean();
    case QuestPlacement::mode: return mode();
  }
  return quantile();
}

double Quest::mean() const {
  double p = 0.0, px = 0.0;
  for (std::size_t k = 0; k < pdf_.size(); ++k) {
    p += pdf_[k];
    px += pdf_[k] * x_[k];
  }
  return spec_.t_guess + px / p;
}

double Quest::sd() const {
  double p = 0.0, px = 0.0, pxx = 0.0;
  for (std::size_t k = 0; k < pdf_.size(); ++k) {
    p += pdf_[k];
    px += pdf_[k] * x_[k];
    pxx += pdf_[k] * x_[k] * x_[k];
  }
  return std::sqrt(pxx / p - (px / p) * (px / p));
}

double Quest::mode() const {
  const auto it = std::max_element(pdf_.begin(), pdf_.end());
  return x_[static_cast<std::size_t>(it - pdf_.begin())] + spec_.t_guess;
}

double Quest::quantile(double quantile_order) const {
  // QuestQuantile: interpolate the cumulative pdf over its strictly increasing points.
  std::vector<double> cumulative_points, x_points;
  double cumulative = 0.0;
  double previous = -1.0;
  for (std::size_t k = 0; k < pdf_.size(); ++k) {
    cumulative += pdf_[k];
    if (cumulative != previous) {
      cumulative_points.push_back(cumulative);
      x_points.push_back(x_[k]);
    }
    previous = cumulative;
  }
  if (cumulative_points.size() < 2) throw std::runtime_error("QUEST '" + spec_.name + "': pdf has fewer than 2 points");
  return spec_.t_guess + interpolate(cumulative_points, x_points, quantile_order * cumulative);
}

}  // namespace glarelab
