#pragma once
// QUEST (Watson & Pelli 1983, "QUEST: a Bayesian adaptive psychometric method", Perception &
// Psychophysics 33(2), 113-120), computed exactly as Psychtoolbox's QuestCreate, QuestRecompute,
// QuestUpdate, QuestMean, QuestSd, QuestMode and QuestQuantile (and PsychoPy's QuestObject, a
// port of them), so results can be compared with either to rounding error.
//
// Intensities are on QUEST's abstract scale, usually log10 of the stimulus strength. The
// posterior over threshold t lives on a grid t = t_guess + i * grain, i = -dim/2 .. dim/2,
// dim = 2 * ceil(range / grain / 2). Each response multiplies it by the Weibull
//   p(x) = delta*gamma + (1 - delta) * (1 - (1 - gamma) * exp(-10^(beta * (x + x_threshold))))
// at x = intensity - t, with the intensity rounded to the grid; x_threshold shifts the function
// so that p(0) = p_threshold (Watson & Pelli 1983, eq. 1 and section "The psychometric function").
#include <optional>
#include <string>
#include <vector>

namespace glarelab {

enum class QuestPlacement { quantile, mean, mode };

QuestPlacement parse_quest_placement(const std::string& name);  // std::invalid_argument otherwise
std::string to_string(QuestPlacement placement);

struct QuestSpec {
  std::string name = "quest";
  double t_guess = 0.0;      // prior mean, intensity units (log10)
  double t_guess_sd = 1.0;   // prior SD, intensity units
  double p_threshold = 0.82; // proportion correct that defines threshold
  double beta = 3.5;         // Weibull slope
  double delta = 0.01;       // lapse: fraction of blind presses
  double gamma = 0.5;        // guess rate (1 / alternatives)
  double grain = 0.01;       // grid step, intensity units
  double range = 5.0;        // grid width, intensity units, centred on t_guess
  QuestPlacement placement = QuestPlacement::quantile;
  std::optional<double> quantile_order;  // empty: King-Smith et al. (1994) optimum from QuestRecompute
  int n_trials = 40;
  std::optional<double> min_value;
  std::optional<double> max_value;
};

// std::invalid_argument for parameters QUEST cannot use (sd, grain, range <= 0; gamma, delta,
// p_threshold outside (0, 1); a Weibull whose range omits p_threshold; n_trials < 1).
void validate_quest_spec(const QuestSpec& spec);

class Quest {
 public:
  explicit Quest(QuestSpec spec);

  const QuestSpec& spec() const { return spec_; }
  // The first trial shows t_guess; later ones the placement statistic of the posterior, clamped
  // to [min_value, max_value] (PsychoPy QuestHandler).
  double next_intensity() const { return next_intensity_; }
  bool finished() const { return trial_count() >= spec_.n_trials; }
  // QuestUpdate with the intensity shown and the response, then choose the next intensity.
  void add_response(double intensity, bool correct);
  void add_response(bool correct) { add_response(next_intensity_, correct); }

  double mean() const;                           // QuestMean
  double sd() const;                             // QuestSd
  double mode() const;                           // QuestMode (first maximum)
  double quantile(double quantile_order) const;  // QuestQuantile
  double quantile() const { return quantile(quantile_order_); }
  double quantile_order() const { return quantile_order_; }
  double x_threshold() const { return x_threshold_; }

  int trial_count() const { return static_cast<int>(intensities_.size()); }
  const std::vector<double>& intensities() const { return intensities_; }
  const std::vector<bool>& responses() const { return responses_; }
  const std::vector<double>& grid_offsets() const { return x_; }  // x: t - t_guess
  const std::vector<double>& posterior() const { return pdf_; }   // normalised

 private:
  double placement_value() const;

  QuestSpec spec_;
  int dim_ = 0;
  std::vector<double> x_;    // dim + 1 threshold offsets
  std::vector<double> pdf_;  // posterior over x_
  std::vector<double> p2_;   // 2 dim + 1 samples of the shifted Weibull at x2 = (-dim..dim) grain
  double x_threshold_ = 0.0;
  double quantile_order_ = 0.5;
  double next_intensity_ = 0.0;
  std::vector<double> intensities_;
  std::vector<bool> responses_;
};

}  // namespace glarelab
