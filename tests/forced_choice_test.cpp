#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "protocols/forced_choice.h"
#include "protocols/json_text.h"

namespace glarelab {
namespace {

Experiment design(std::uint64_t seed, int repetitions, bool counterbalance) {
  Experiment e;
  e.name = "design";
  e.seed = seed;
  e.forced_choice.repetitions = repetitions;
  e.forced_choice.counterbalance_sides = counterbalance;
  const char* pairs[][3] = {{"p1", "a", "b"}, {"p2", "b", "c"}, {"p3", "a", "c"}, {"same", "a", "a2"}};
  int number = 1;
  for (const auto& pair : pairs) {
    ConditionRow row;
    row.fields = {{"name", pair[0]}, {"scene_a", pair[1]}, {"scene_b", pair[2]}};
    row.number = number++;
    e.conditions.push_back(row);
  }
  return e;
}

const std::map<std::string, double> kPeaks = {{"a", 100.0}, {"a2", 100.0}, {"b", 200.0}, {"c", 50.0}};

std::vector<std::string> order_of(const std::vector<TrialPlan>& trials) {
  std::vector<std::string> order;
  for (const TrialPlan& t : trials) order.push_back(t.condition_name + ":" + t.scenes[0]);
  return order;
}

TEST(ForcedChoice, CountsIndicesAndBalance) {
  const Experiment e = design(11, 3, true);
  const std::vector<TrialPlan> trials = build_forced_choice_trials(e, kPeaks);
  ASSERT_EQ(trials.size(), 4u * 3u * 2u);
  std::map<std::pair<std::string, std::string>, int> left_counts;  // (condition, scene on the left)
  for (std::size_t i = 0; i < trials.size(); ++i) {
    const TrialPlan& t = trials[i];
    EXPECT_EQ(t.trial_index, static_cast<int>(i));
    EXPECT_EQ(t.block, 0);
    EXPECT_EQ(t.procedure, "forced_choice");
    EXPECT_EQ(t.positions, (std::vector<std::string>{"left", "right"}));
    EXPECT_EQ(t.allowed_responses, (std::vector<std::string>{"left", "right"}));
    EXPECT_EQ(t.stimulus_frames, e.forced_choice.stimulus_frames);
    EXPECT_EQ(t.question, e.forced_choice.question);
    ++left_counts[{t.condition_name, t.scenes[0]}];
  }
  // Every row shows each of its scenes on the left exactly `repetitions` times.
  for (const ConditionRow& row : e.conditions) {
    EXPECT_EQ((left_counts[{row.name(), *row.find("scene_a")}]), 3);
    EXPECT_EQ((left_counts[{row.name(), *row.find("scene_b")}]), 3);
  }
}

TEST(ForcedChoice, WithoutCounterbalancingSceneAIsLeft) {
  const std::vector<TrialPlan> trials = build_forced_choice_trials(design(3, 2, false), kPeaks);
  ASSERT_EQ(trials.size(), 8u);
  for (const TrialPlan& t : trials) {
    if (t.condition_name == "p1") {
      EXPECT_EQ(t.scenes, (std::vector<std::string>{"a", "b"}));
    }
  }
}

TEST(ForcedChoice, OrderDependsOnlyOnSeed) {
  const auto first = order_of(build_forced_choice_trials(design(5, 2, true), kPeaks));
  const auto again = order_of(build_forced_choice_trials(design(5, 2, true), kPeaks));
  const auto other = order_of(build_forced_choice_trials(design(6, 2, true), kPeaks));
  EXPECT_EQ(first, again);
  EXPECT_NE(first, other);
}

TEST(ForcedChoice, CorrectResponseLuminanceAndJson) {
  Experiment e = design(9, 1, true);
  e.forced_choice.responses = {"f", "j"};
  for (const TrialPlan& t : build_forced_choice_trials(e, kPeaks)) {
    ASSERT_EQ(t.source_luminance_cd_m2.size(), 2u);
    EXPECT_EQ(t.source_luminance_cd_m2[0], kPeaks.at(t.scenes[0]));
    EXPECT_EQ(t.source_luminance_cd_m2[1], kPeaks.at(t.scenes[1]));
    if (t.condition_name == "same") {
      EXPECT_EQ(t.correct_response, "");
    } else {
      EXPECT_EQ(t.correct_response, t.source_luminance_cd_m2[0] > t.source_luminance_cd_m2[1] ? "f" : "j");
    }
    const auto row = std::find_if(e.conditions.begin(), e.conditions.end(),
                                  [&](const ConditionRow& r) { return r.name() == t.condition_name; });
    ASSERT_NE(row, e.conditions.end());
    const std::string expected = "{\"name\":\"" + t.condition_name + "\",\"scene_a\":\"" + *row->find("scene_a") +
                                 "\",\"scene_b\":\"" + *row->find("scene_b") + "\",\"left\":\"" + t.scenes[0] +
                                 "\",\"right\":\"" + t.scenes[1] + "\"}";
    EXPECT_EQ(t.condition_json, expected);
  }
}

TEST(ForcedChoice, MissingLuminanceIsAnError) {
  EXPECT_THROW(build_forced_choice_trials(design(1, 1, true), {{"a", 1.0}}), std::invalid_argument);
}

TEST(ForcedChoice, Scoring) {
  TrialPlan plan;
  plan.allowed_responses = {"left", "right"};
  plan.correct_response = "right";
  EXPECT_EQ(score_forced_choice(plan, {"right", 0.5}).correct, 1);
  EXPECT_EQ(score_forced_choice(plan, {"left", 0.5}).correct, 0);
  EXPECT_EQ(score_forced_choice(plan, {"left", 0.5}).response, "left");
  EXPECT_FALSE(score_forced_choice(plan, {"abort", std::nullopt}).correct.has_value());
  plan.correct_response.clear();
  EXPECT_FALSE(score_forced_choice(plan, {"right", 0.5}).correct.has_value());
}

TEST(JsonText, EscapesStrings) {
  EXPECT_EQ(json_quote("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(json_quote("x\ny\t\x01"), "\"x\\ny\\t\\u0001\"");
  EXPECT_EQ(json_quote("caf\xC3\xA9"), "\"caf\xC3\xA9\"");
  EXPECT_EQ(json_quote("bad\xFF"), "\"bad\\ufffd\"");
  EXPECT_EQ(json_quote("\xED\xA0\x80"), "\"\\ufffd\\ufffd\\ufffd\"");  // UTF-8-encoded surrogate
  EXPECT_EQ(JsonObjectWriter().add("k", "v").add("n\"", "").str(), "{\"k\":\"v\",\"n\\\"\":\"\"}");
  EXPECT_EQ(JsonObjectWriter().str(), "{}");
}

}  // namespace
}  // namespace glarelab
