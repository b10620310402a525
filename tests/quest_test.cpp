// QUEST against a second, deliberately plain implementation written here from Watson & Pelli
// (1983): posterior(t) proportional to prior(t) * prod_k psi(I_k - t)^r_k (1 - psi(I_k - t))^(1-r_k)
// on the grid t = t_guess + i grain, with psi the Weibull shifted so psi(0) = p_threshold. It
// shares no code with protocols/quest.cpp (which works by table lookups, as Psychtoolbox does).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "protocols/psychometric_observer.h"
#include "protocols/quest.h"

namespace glarelab {
namespace {

struct PlainQuest {
  double t_guess, sd, p_threshold, beta, delta, gamma, grain, range;
  std::vector<double> t, w;
  double x_threshold = 0.0;

  double psi_unshifted(double x) const {
    return delta * gamma + (1 - delta) * (1 - (1 - gamma) * std::exp(-std::pow(10.0, beta * x)));
  }

  void init() {
    const int dim = 2 * static_cast<int>(std::ceil(range / grain / 2.0));
    // Psychtoolbox defines x_threshold by linear interpolation of the Weibull sampled on
    // (-dim..dim) * grain; reproduce that definition directly: find the bracketing samples.
    for (int i = -dim; i < dim; ++i) {
      const double a = psi_unshifted(i * grain), b = psi_unshifted((i + 1) * grain);
      if (a <= p_threshold && p_threshold < b) {
        x_threshold = i * grain + (p_threshold - a) / (b - a) * grain;
        break;
      }
    }
    for (int i = -dim / 2; i <= dim / 2; ++i) {
      const double x = i * grain;
      t.push_back(t_guess + x);
      w.push_back(std::exp(-0.5 * (x / sd) * (x / sd)));
    }
  }
  void update(double intensity, bool correct) {
    const double on_grid = t_guess + grain * std::round((intensity - t_guess) / grain);
    for (std::size_t k = 0; k < t.size(); ++k) {
      const double p = psi_unshifted(on_grid - t[k] + x_threshold);
      w[k] *= correct ? p : 1 - p;
    }
  }
  double total() const {
    double s = 0;
    for (double v : w) s += v;
    return s;
  }
  double mean() const {
    double s = 0;
    for (std::size_t k = 0; k < t.size(); ++k) s += w[k] * t[k];
    return s / total();
  }
  double sd_() const {
    const double m = mean();
    double s = 0;
    for (std::size_t k = 0; k < t.size(); ++k) s += w[k] * (t[k] - m) * (t[k] - m);
    return std::sqrt(s / total());
  }
  double mode() const {
    std::size_t best = 0;
    for (std::size_t k = 1; k < t.size(); ++k)
      if (w[k] > w[best]) best = k;
    return t[best];
  }
  // Inverse of the piecewise-linear cumulative through (cumsum_k, t_k).
  double quantile(double q) const {
    const double target = q * total();
    double c_prev = 0, c = 0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      c_prev = c;
      c += w[k];
      if (c >= target && k > 0) return t[k - 1] + (target - c_prev) / (c - c_prev) * (t[k] - t[k - 1]);
    }
    return t.back();
  }
};

TEST(Quest, MatchesPlainPosteriorAfterFixedResponses) {
  QuestSpec spec;
  spec.t_guess = -1.0;
  spec.t_guess_sd = 0.8;
  spec.p_threshold = 0.82;
  spec.beta = 3.5;
  spec.delta = 0.01;
  spec.gamma = 0.5;
  spec.grain = 0.01;
  spec.range = 5.0;
  spec.n_trials = 12;
  Quest quest(spec);
  PlainQuest plain{spec.t_guess, spec.t_guess_sd, spec.p_threshold, spec.beta, spec.delta,
                   spec.gamma, spec.grain, spec.range, {}, {}};
  plain.init();
  EXPECT_NEAR(quest.x_threshold(), plain.x_threshold, 1e-12);

  // King-Smith et al. (1994) quantile order for these parameters, from QuestRecompute's formula
  // at the Weibull's asymptotes, which the grid ends reach to 1e-16: pL = gamma = 0.5 and
  // pH = 1 - delta (1 - gamma) = 0.995.
  const double pl = 0.5, ph = 0.995, eps = 1e-14;
  double pe = ph * std::log(ph + eps) - pl * std::log(pl + eps) + (1 - ph + eps) * std::log(1 - ph + eps) -
              (1 - pl + eps) * std::log(1 - pl + eps);
  pe = 1 / (1 + std::exp(pe / (pl - ph)));
  EXPECT_NEAR(quest.quantile_order(), (pe - pl) / (ph - pl), 1e-9);

  const std::vector<int> responses = {1, 1, 0, 1, 1, 1, 0, 1, 0, 1, 1, 1};
  std::vector<double> shown;
  for (int r : responses) {
    const double intensity = quest.next_intensity();
    shown.push_back(intensity);
    // The plain implementation chooses its own next intensity with the same placement rule.
    if (shown.size() == 1) {
      EXPECT_DOUBLE_EQ(intensity, spec.t_guess);
    } else {
      EXPECT_NEAR(intensity, plain.quantile(quest.quantile_order()), 1e-6) << "trial " << shown.size() - 1;
    }
    quest.add_response(r == 1);
    plain.update(intensity, r == 1);
  }
  EXPECT_EQ(quest.intensities(), shown);
  EXPECT_NEAR(quest.mean(), plain.mean(), 1e-6);
  EXPECT_NEAR(quest.sd(), plain.sd_(), 1e-6);
  EXPECT_NEAR(quest.mode(), plain.mode(), 1e-9);
  for (double q : {0.05, 0.25, 0.5, 0.95}) EXPECT_NEAR(quest.quantile(q), plain.quantile(q), 1e-6) << q;
  EXPECT_TRUE(quest.finished());
  // 9 of 12 right (75 %) is below p_threshold (82 %): the estimate moved up from the guess.
  EXPECT_GT(quest.mean(), spec.t_guess);
}

TEST(Quest, MeanAndModePlacement) {
  for (QuestPlacement placement : {QuestPlacement::mean, QuestPlacement::mode}) {
    QuestSpec spec;
    spec.t_guess = 0.5;
    spec.t_guess_sd = 1.0;
    spec.placement = placement;
    Quest quest(spec);
    PlainQuest plain{0.5, 1.0, spec.p_threshold, spec.beta, spec.delta, spec.gamma, spec.grain, spec.range, {}, {}};
    plain.init();
    for (int r : {0, 1, 1, 0, 1}) {
      const double intensity = quest.next_intensity();
      quest.add_response(r == 1);
      plain.update(intensity, r == 1);
      const double expected = placement == QuestPlacement::mean ? plain.mean() : plain.mode();
      EXPECT_NEAR(quest.next_intensity(), expected, 1e-6) << to_string(placement);
    }
  }
}

TEST(Quest, RefusesUnusableParameters) {
  QuestSpec spec;
  spec.t_guess_sd = 0;
  EXPECT_THROW(Quest{spec}, std::invalid_argument);
  spec.t_guess_sd = 1;
  spec.p_threshold = 0.4;  // below the guess rate
  EXPECT_THROW(Quest{spec}, std::invalid_argument);
  EXPECT_THROW(parse_quest_placement("median"), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab
