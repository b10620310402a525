// Adaptive procedures against a simulated observer of known psychometric function: 100 seeded
// runs each, pure logic (no rendering).
#include <gtest/gtest.h>

#include <cmath>

#include "protocols/psychometric_observer.h"
#include "protocols/quest.h"
#include "protocols/staircase.h"

namespace glarelab {
namespace {

TEST(PsychometricFunction, InverseAndKnownPoints) {
  const PsychometricFunction f{2.0, 3.5, 0.5, 0.02};
  // At I = threshold: (I/a)^b = 1, so p = 0.5 + 0.48 (1 - 1/e).
  EXPECT_NEAR(f.p_correct(2.0), 0.5 + 0.48 * (1 - std::exp(-1.0)), 1e-15);
  EXPECT_DOUBLE_EQ(f.p_correct(0.0), 0.5);
  EXPECT_NEAR(f.intensity_at(f.p_correct(1.3)), 1.3, 1e-12);
  EXPECT_THROW(f.intensity_at(0.99), std::invalid_argument);
}

TEST(PsychometricObserver, RespondsWithItsProbability) {
  const PsychometricObserver observer({1.0, 3.5, 0.5, 0.02}, 5);
  const double intensity = 1.2;
  int correct = 0;
  constexpr int kTrials = 20000;
  for (int i = 0; i < kTrials; ++i) correct += observer.respond(intensity, static_cast<std::uint64_t>(i));
  const double p = observer.function().p_correct(intensity);
  EXPECT_NEAR(static_cast<double>(correct) / kTrials, p, 4 * std::sqrt(p * (1 - p) / kTrials));
}

// 1-up/3-down converges where p^3 = 1/2, p = 0.794 (Levitt 1971, "Transformed up-down methods in
// psychoacoustics", JASA 49(2B), table I). Threshold estimate: mean of the last 8 of 14 reversals.
TEST(AdaptiveConvergence, OneUpThreeDownFindsThe794PercentPoint) {
  const PsychometricFunction f{0.3, 3.5, 0.5, 0.01};
  const double target_log10 = std::log10(f.intensity_at(std::pow(0.5, 1.0 / 3.0)));
  int within = 0;
  for (std::uint64_t seed = 1; seed <= 100; ++seed) {
    StaircaseSpec spec;
    spec.start_value = 1.0;
    spec.step_sizes = {4, 2, 1};  // dB
    spec.n_up = 1;
    spec.n_down = 3;
    spec.n_reversals = 14;
    Staircase staircase(spec);
    const PsychometricObserver observer(f, seed);
    std::uint64_t trial = 0;
    while (!staircase.finished()) staircase.add_response(observer.respond(staircase.next_intensity(), trial++));
    const double estimate_log10 = std::log10(staircase.mean_of_last_reversals(8));
    within += std::abs(estimate_log10 - target_log10) <= 0.1;
  }
  std::cout << "1-up/3-down: " << within << "/100 runs within 0.1 log10 of the 79.4% point\n";
  EXPECT_GE(within, 90);
}

// QUEST (40 trials, quantile placement, prior sd 1 log unit centred 0.5 log units off) estimates
// the intensity where the observer is p_threshold correct.
TEST(AdaptiveConvergence, QuestFindsTheThreshold) {
  const PsychometricFunction f{0.3, 3.5, 0.5, 0.01};
  QuestSpec spec;
  spec.p_threshold = 0.82;
  spec.beta = 3.5;
  spec.gamma = 0.5;
  spec.delta = 0.01;
  spec.n_trials = 40;
  const double truth_log10 = std::log10(f.intensity_at(spec.p_threshold));
  spec.t_guess = truth_log10 + 0.5;
  spec.t_guess_sd = 1.0;
  int within = 0;
  for (std::uint64_t seed = 1; seed <= 100; ++seed) {
    Quest quest(spec);
    const PsychometricObserver observer(f, seed);
    std::uint64_t trial = 0;
    while (!quest.finished())
      quest.add_response(observer.respond(std::pow(10.0, quest.next_intensity()), trial++));
    within += std::abs(quest.mean() - truth_log10) <= 0.1;
  }
  std::cout << "QUEST: " << within << "/100 runs within 0.1 log10 of the threshold\n";
  EXPECT_GE(within, 90);
}

}  // namespace
}  // namespace glarelab
