#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "protocols/experiment.h"
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
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {  // bad input (exit 2), where the missing answer belongs
    EXPECT_EQ(std::string(error.what()), path + ":3: response script holds 2 responses; trial 2 needs response 3");
  }
  const std::string missing = (dir.path() / "none.txt").string();
  try {
    make_script_observer(missing);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(std::string(error.what()), missing + ": response script: file not found");
  }
}

// A comparison of two conditions without a right answer (equal luminance, or a preference
// question): the stated preference sets the choice frequency.
TrialPlan comparison(int index, const std::string& left_condition, const std::string& right_condition) {
  TrialPlan plan = plan_with(index, 100.0, 100.0);
  plan.position_conditions = {left_condition, right_condition};
  return plan;
}

TEST(SimulatedObserver, PreferencesSetTheChoiceFrequencyOfEachPair) {
  SimulatedObserverSpec spec;
  spec.preferences = {{"dynamic", "static", 0.75, {}}, {"static", "control", 0.3, {}}};
  const auto observer = make_simulated_observer(spec, 2009);
  constexpr int kTrials = 4000;
  // Binomial tolerance: 4 standard deviations of the frequency, sqrt(p (1 - p) / n).
  const auto tolerance = [](double p) { return 4.0 * std::sqrt(p * (1.0 - p) / kTrials); };
  struct Case {
    std::string left, right;
    double p_left;  // probability of choosing the left side
  };
  const std::vector<Case> cases = {{"dynamic", "static", 0.75},  // as written
                                   {"static", "dynamic", 0.25},  // swapped sides: 1 - p for the left
                                   {"static", "control", 0.3},
                                   {"control", "static", 0.7},
                                   {"dynamic", "control", 0.5}};  // no preference: either side
  for (const Case& c : cases) {
    int lefts = 0;
    for (int i = 0; i < kTrials; ++i) lefts += observer->respond(comparison(i, c.left, c.right)).value == "left";
    EXPECT_NEAR(static_cast<double>(lefts) / kTrials, c.p_left, tolerance(c.p_left)) << c.left << " vs " << c.right;
  }
  // A trial with a right answer is answered by the psychometric function, not the preference:
  // a 1 log10 unit difference is seen but for lapses (2 %), whatever the preference says.
  int correct = 0;
  for (int i = 0; i < kTrials; ++i) {
    TrialPlan plan = comparison(i, "dynamic", "static");
    plan.source_luminance_cd_m2 = {10.0, 100.0};
    plan.correct_response = "right";
    correct += observer->respond(plan).value == "right";
  }
  EXPECT_NEAR(static_cast<double>(correct) / kTrials, 1.0 - spec.lapse, tolerance(1.0 - spec.lapse));
}

TEST(SimulatedObserver, PreferencesInTheExperimentFile) {
  const std::string base = R"(
[experiment]
name = "prefs"
[scenes]
s = { file = "/s.exr" }
[procedure]
type = "forced_choice"
[[conditions.rows]]
scene_a = "s"
scene_b = "s"
condition_a = "dynamic"
condition_b = "static"
[observer.simulated.preferences]
)";
  const Experiment e = parse_experiment_text(base + "\"dynamic>static\" = 0.8\n", "p.toml", "/");
  ASSERT_EQ(e.simulated_observer.preferences.size(), 1u);
  EXPECT_EQ(e.simulated_observer.preferences[0].preferred, "dynamic");
  EXPECT_EQ(e.simulated_observer.preferences[0].other, "static");
  EXPECT_EQ(e.simulated_observer.preferences[0].probability, 0.8);
  const std::string resolved = resolved_config_toml(e);
  EXPECT_EQ(resolved_config_toml(parse_experiment_text(resolved, "<r>", "/")), resolved);
  EXPECT_NE(resolved.find("[observer.simulated.preferences]"), std::string::npos) << resolved;
  auto error = [&](const std::string& entries) -> std::string {
    try {
      parse_experiment_text(base + entries, "p.toml", "/");
    } catch (const ConfigError& failure) {
      return failure.what();
    }
    return "no error";
  };
  EXPECT_NE(error("\"dynamic>static\" = 1.5\n").find("p.toml:14:"), std::string::npos);
  EXPECT_NE(error("\"dynamic>static\" = 1.5\n").find("probability in [0, 1]"), std::string::npos);
  EXPECT_NE(error("\"dynamic\" = 0.5\n").find("\"PREFERRED>OTHER\""), std::string::npos);
  EXPECT_NE(error("\"dynamic>dynamic\" = 0.5\n").find("preferred to itself"), std::string::npos);
  EXPECT_NE(error("\"dynamic>statc\" = 0.5\n").find("no condition row shows 'statc'"), std::string::npos);
  EXPECT_NE(error("\"dynamic>static\" = 0.5\n\"static>dynamic\" = 0.5\n").find("already has a preference"),
            std::string::npos);
  EXPECT_NE(error("\"dynamic>static\" = \"high\"\n").find("expected"), std::string::npos);
}

}  // namespace
}  // namespace glarelab
