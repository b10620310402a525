// Double adjustment: the design, the seeded start values, the scoring of "L R" responses, the
// keys, and the matching observer.
#include <gtest/gtest.h>

#include <cmath>

#include "protocols/adjustment_procedure.h"
#include "protocols/observer.h"
#include "core/random.h"
#include "runner/session/adjustment_keys.h"

namespace glarelab {
namespace {

const std::map<std::string, double> kPeaks = {{"target", 120.0}, {"spot", 80.0}};

Experiment adjustment_experiment() {
  Experiment e;
  e.seed = 5;
  e.procedure = "adjustment";
  e.adjustment.repetitions = 3;
  e.adjustment.start_range_log10 = 0.3;
  ConditionRow row;
  row.fields = {{"name", "c"}, {"target", "target"}, {"comparison", "spot"}};
  row.number = 1;
  e.conditions.push_back(row);
  return e;
}

TEST(AdjustmentProcedure, StartValuesComeFromTheAdjustmentStartStream) {
  const Experiment e = adjustment_experiment();
  const auto trials = build_adjustment_trials(e, kPeaks);
  ASSERT_EQ(trials.size(), 3u);
  const CounterRandom random(e.seed, RandomStream::adjustment_start);
  for (const TrialPlan& plan : trials) {
    ASSERT_EQ(plan.adjustment_start_cd_m2.size(), 2u);
    for (std::uint32_t spot = 0; spot < 2; ++spot) {
      const double u = 2.0 * random.uniform(static_cast<std::uint64_t>(plan.trial_index), spot) - 1.0;
      EXPECT_DOUBLE_EQ(plan.adjustment_start_cd_m2[spot], 120.0 * std::pow(10.0, 0.3 * u));
    }
    EXPECT_EQ(plan.scenes, (std::vector<std::string>{"spot", "target", "spot"}));
    // The spot image (peak 80) is scaled to show the start luminance.
    EXPECT_NEAR(plan.scene_scale[0] * 80.0, plan.adjustment_start_cd_m2[0], 1e-9);
    EXPECT_NEAR(plan.scene_scale[2] * 80.0, plan.adjustment_start_cd_m2[1], 1e-9);
    EXPECT_EQ(plan.scene_scale[1], 1.0);
  }
}

TEST(AdjustmentProcedure, ScoresTheMeanOfBothSettings) {
  const TrialPlan plan = build_adjustment_trials(adjustment_experiment(), kPeaks)[0];
  const TrialOutcome two = score_adjustment(plan, {format_adjustment_response(100.0, 130.5), 2.0});
  EXPECT_EQ(two.adjustment_settings_cd_m2, (std::vector<double>{100.0, 130.5}));
  EXPECT_DOUBLE_EQ(*two.intensity, 115.25);
  EXPECT_FALSE(two.correct.has_value());
  const TrialOutcome one = score_adjustment(plan, {"90", std::nullopt});
  EXPECT_EQ(one.adjustment_settings_cd_m2, (std::vector<double>{90.0, 90.0}));
  EXPECT_THROW(score_adjustment(plan, {"left", 1.0}), std::invalid_argument);
  EXPECT_THROW(score_adjustment(plan, {"1 2 3", 1.0}), std::invalid_argument);
  EXPECT_THROW(score_adjustment(plan, {"-4 2", 1.0}), std::invalid_argument);
  // The response text round-trips the doubles exactly (resume replays it).
  const double awkward = 100.0 * std::pow(10.0, 0.1 * 7);
  EXPECT_EQ(score_adjustment(plan, {format_adjustment_response(awkward, awkward), 1.0}).adjustment_settings_cd_m2[0],
            awkward);
}

TEST(AdjustmentProcedure, KeysStepBothSpotsInLogUnits) {
  AdjustmentSpec spec;
  spec.coarse_step_log10 = 0.1;
  spec.fine_step_log10 = 0.01;
  EXPECT_DOUBLE_EQ(*adjustment_factor("up", spec), std::pow(10.0, 0.1));
  EXPECT_DOUBLE_EQ(*adjustment_factor("down", spec), std::pow(10.0, -0.1));
  EXPECT_DOUBLE_EQ(*adjustment_factor("right", spec), std::pow(10.0, 0.01));
  EXPECT_DOUBLE_EQ(*adjustment_factor("left", spec), std::pow(10.0, -0.01));
  EXPECT_FALSE(adjustment_factor("a", spec).has_value());
  EXPECT_TRUE(accepts_adjustment("enter"));
  EXPECT_FALSE(accepts_adjustment("up"));
}

TEST(AdjustmentProcedure, MatchingObserverScattersAroundTheTarget) {
  Experiment e = adjustment_experiment();
  e.adjustment.repetitions = 400;
  SimulatedObserverSpec spec;
  spec.match_sd_log10 = 0.05;
  auto observer = make_simulated_observer(spec, 17);
  double sum = 0.0, sum_sq = 0.0;
  int n = 0;
  for (const TrialPlan& plan : build_adjustment_trials(e, kPeaks)) {
    const TrialOutcome outcome = score_adjustment(plan, observer->respond(plan));
    for (double setting : outcome.adjustment_settings_cd_m2) {
      const double error_log10 = std::log10(setting / 120.0);
      sum += error_log10;
      sum_sq += error_log10 * error_log10;
      ++n;
    }
  }
  const double mean = sum / n;
  const double sd = std::sqrt(sum_sq / n - mean * mean);
  // 800 settings: the mean's standard error is 0.05 / sqrt(800) = 0.0018.
  EXPECT_NEAR(mean, 0.0, 0.008);
  EXPECT_NEAR(sd, 0.05, 0.005);
}

}  // namespace
}  // namespace glarelab
