// Likert ratings: one trial per scene x category x repetition, answered by a number.
#include <gtest/gtest.h>

#include <set>

#include "protocols/observer.h"
#include "protocols/rating_procedure.h"

namespace glarelab {
namespace {

Experiment rating_experiment() {
  Experiment e;
  e.seed = 3;
  e.procedure = "rating";
  e.rating.categories = {"glare appearance", "overall"};
  e.rating.scale_points = 7;
  e.rating.repetitions = 2;
  int number = 1;
  for (const char* scene : {"a", "b", "c"}) {
    ConditionRow row;
    row.fields = {{"name", scene}, {"scene", scene}, {"simulated_rating", number == 1 ? "6.4" : "2"}};
    row.number = number++;
    e.conditions.push_back(row);
  }
  return e;
}

TEST(RatingProcedure, EverySceneOnEveryCategory) {
  const auto trials = build_rating_trials(rating_experiment());
  ASSERT_EQ(trials.size(), 3u * 2u * 2u);
  std::multiset<std::string> cells;
  for (const TrialPlan& plan : trials) {
    EXPECT_EQ(plan.allowed_responses, (std::vector<std::string>{"1", "2", "3", "4", "5", "6", "7"}));
    EXPECT_TRUE(plan.correct_response.empty());
    ASSERT_EQ(plan.scenes.size(), 1u);
    cells.insert(plan.scenes[0] + "/" + plan.question);
  }
  for (const std::string& cell : cells) EXPECT_EQ(cells.count(cell), 2u) << cell;
  EXPECT_EQ(std::set<std::string>(cells.begin(), cells.end()).size(), 6u);
}

TEST(RatingProcedure, SimulatedRatingsFollowTheConditionMean) {
  Experiment e = rating_experiment();
  e.rating.repetitions = 200;
  SimulatedObserverSpec spec;
  spec.rating_sd = 0.7;
  auto observer = make_simulated_observer(spec, 11);
  double sum_a = 0.0, sum_b = 0.0;
  int n_a = 0, n_b = 0;
  for (const TrialPlan& plan : build_rating_trials(e)) {
    const int rating = std::stoi(observer->respond(plan).value);
    ASSERT_GE(rating, 1);
    ASSERT_LE(rating, 7);
    if (plan.scenes[0] == "a") {
      sum_a += rating;
      ++n_a;
    } else {
      sum_b += rating;
      ++n_b;
    }
  }
  // Expected means of round(N(mu, 0.7)) clamped to 1..7, summed over the normal's mass per
  // point: 6.3406 for mu = 6.4 and 2.0162 for mu = 2. 400 and 800 ratings: standard errors
  // about 0.03 and 0.025, so 0.12 is four of them.
  EXPECT_NEAR(sum_a / n_a, 6.3406, 0.12);
  EXPECT_NEAR(sum_b / n_b, 2.0162, 0.12);
}

}  // namespace
}  // namespace glarelab
