#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "protocols/observer.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

TrialPlan plan_with(int index, double left, double right) {
  TrialPlan plan;
  plan.trial_index = index;
  plan.procedure = "forced_choice";
  plan.positions = {"left", "right"};
  plan.scenes = {"x", "y"};
  plan.source_luminance_cd_m2 = {left, right};
  plan.allowed_responses = {"left", "right"};
  if (left != right) plan.correct_response = left > right ? "left" : "right";
  return plan;
}

// Proportion correct over 4000 trials against the Weibull 2-AFC form
// p = 0.5 + (1 - 0.5 - lapse) * (1 - exp(-(d/alpha)^beta)), within three binomial standard errors.
TEST(SimulatedObserver, ChoiceFrequencyMatchesPsychometricFunction) {
  SimulatedObserverSpec spec;
  spec.threshold_log10 = 0.05;
  spec.slope = 3.5;
  spec.lapse = 0.02;
  const auto observer = make_simulated_observer(spec, 1234);
  constexpr int kTrials = 4000;
  const double right = 100.0;
  const double left = right * std::pow(10.0, spec.threshold_log10);  // d = threshold
  const double expected = 0.5 + (1.0 - 0.5 - spec.lapse) * (1.0 - std::exp(-1.0));
  int correct = 0;
  for (int i = 0; i < kTrials; ++i) correct += observer->respond(plan_with(i, left, right)).value == "left";
  const double se = std::sqrt(expected * (1.0 - expected) / kTrials);
  EXPECT_NEAR(static_cast<double>(correct) / kTrials, expected, 3.0 * se);

  // d = 0: no right answer, each response half the time.
  int lefts = 0;
  for (int i = 0; i < kTrials; ++i) lefts += observer->respond(plan_with(i, right, right)).value == "left";
  EXPECT_NEAR(static_cast<double>(lefts) / kTrials, 0.5, 3.0 * std::sqrt(0.25 / kTrials));
}

TEST(SimulatedObserver, LargeDifferencesAreRightButForLapses) {
  SimulatedObserverSpec spec;
  spec.lapse = 0.04;
  const auto observer = make_simulated_observer(spec, 99);
  constexpr int kTrials = 4000;
  int correct = 0;
  for (int i = 0; i < kTrials; ++i) correct += observer->respond(plan_with(i, 10.0, 1000.0)).value == "right";
  const double expected = 1.0 - spec.lapse;
  EXPECT_NEAR(static_cast<double>(correct) / kTrials, expected, 3.0 * std::sqrt(expected * (1 - expected) / kTrials));
}

TEST(SimulatedObserver, DeterministicPerTrialIndex) {
  SimulatedObserverSpec spec;
  const auto a = make_simulated_observer(spec, 7);
  const auto b = make_simulated_observer(spec, 7);
  EXPECT_EQ(a->description(), "simulated");
  // b answers the same trials in reverse order, as a resumed session would answer out of turn.
  std::vector<Response> forward;
  for (int i = 0; i < 50; ++i) forward.push_back(a->respond(plan_with(i, 100.0, 112.0)));
  for (int i = 49; i >= 0; --i) {
    const Response r = b->respond(plan_with(i, 100.0, 112.0));
    EXPECT_EQ(r.value, forward[static_cast<std::size_t>(i)].value);
    ASSERT_TRUE(r.response_time_s.has_value());
    EXPECT_EQ(*r.response_time_s, *forward[static_cast<std::size_t>(i)].response_time_s);
    EXPECT_GT(*r.response_time_s, 0.0);
  }
}

TEST(SimulatedObserver, ResponseTimesHaveTheConfiguredMedian) {
  SimulatedObserverSpec spec;
  spec.response_time_median_s = 0.8;
  const auto observer = make_simulated_observer(spec, 3);
  std::vector<double> times;
  for (int i = 0; i < 4001; ++i) times.push_back(*observer->respond(plan_with(i, 1.0, 2.0)).response_time_s);
  std::nth_element(times.begin(), times.begin() + 2000, times.end());
  // ln t ~ N(ln 0.8, 0.25^2): the sample median's log is within a few 0.25*sqrt(pi/2/n) of ln 0.8.
  EXPECT_NEAR(std::log(times[2000]), std::log(0.8), 4.0 * 0.25 * std::sqrt(3.14159 / 2.0 / 4001.0));
}

TEST(ScriptObserver, MapsOneZeroAndNamesByTrialIndex) {
  test::ScratchDir dir;
  const std::string path = dir.write("answers.txt", "# answers\n1\n\n0\n  left\nright\n1\nabort\n");
  const auto observer = make_script_observer(path);
  EXPECT_EQ(observer->description(), "script:" + path);
  EXPECT_EQ(observer->respond(plan_with(0, 2.0, 1.0)).value, "left");   // 1 = correct
  EXPECT_EQ(observer->respond(plan_with(1, 2.0, 1.0)).value, "right");  // 0 = the other
  EXPECT_EQ(observer->respond(plan_with(2, 2.0, 1.0)).value, "left");
  EXPECT_EQ(observer->respond(plan_with(3, 2.0, 1.0)).value, "right");
  EXPECT_EQ(observer->respond(plan_with(4, 1.0, 1.0)).value, "left");   // 1 without a right answer
  EXPECT_EQ(observer->respond(plan_with(5, 1.0, 1.0)).value, "abort");
  // Entry k answers trial k whatever was asked before (resumed sessions).
  EXPECT_EQ(observer->respond(plan_with(1, 1.0, 2.0)).value, "left");
  EXPECT_FALSE(observer->respond(plan_with(0, 1.0, 2.0)).response_time_s.has_value());
}

TEST(ScriptObserver, RejectsUnknownValuesAtTheirLine) {
  test::ScratchDir dir;
  const std::string path = dir.write("answers.txt", "left\n  maybe\n");
  const auto observer = make_script_observer(path);
  try {
    observer->respond(plan_with(1, 2.0, 1.0));
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(std::string(error.what()),
              path + ":2:3: response 'maybe' is not allowed (allowed: '1', '0', 'left', 'right', 'abort')");
  }
}

TEST(ScriptObserver, RunningOutAndMissingFile) {
  test::ScratchDir dir;
  const std::string path = dir.write("answers.txt", "1\n1\n");
  const auto observer = make_script_observer(path);
  try {
    observer->respond(plan_with(2, 2.0, 1.0));
    FAIL() << "expected runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), "response script " + path + " holds 2 responses; trial 2 needs response 3");
  }
  const std::string missing = (dir.path() / "none.txt").string();
  try {
    make_script_observer(missing);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(std::string(error.what()), missing + ": response script: file not found");
  }
}

}  // namespace
}  // namespace glarelab
