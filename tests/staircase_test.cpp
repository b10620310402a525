// Expected vectors below were traced by hand through PsychoPy's StairHandler algorithm
// (addResponse -> calculateNextIntensity -> _intensityInc/_intensityDec); each case's comments
// give the reasoning for the less obvious steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "protocols/staircase.h"

namespace glarelab {
namespace {

struct StairRun {
  std::vector<double> intensities;
  std::vector<int> reversal_trials;
  std::vector<double> reversal_intensities;
  int trials = 0;
};

StairRun run(const StaircaseSpec& spec, const std::vector<int>& responses) {
  Staircase staircase(spec);
  for (int r : responses) {
    if (staircase.finished()) break;
    staircase.add_response(r == 1);
  }
  EXPECT_TRUE(staircase.finished());
  return {staircase.intensities(), staircase.reversal_trials(), staircase.reversal_intensities(),
          staircase.trial_count()};
}

void expect_doubles(const std::vector<double>& actual, const std::vector<double>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < actual.size(); ++i) EXPECT_DOUBLE_EQ(actual[i], expected[i]) << "at " << i;
}

// lin, steps 4/2/1, 1-up/3-down with the initial 1-up/1-down rule.
// t2 (wrong after two rights) is the first reversal: the step size moves to 2 first and the
// trial still steps up by the initial rule (2 -> 4). From then on 3 rights are needed to go
// down; t5 is a reversal (up -> down) at step 1, t6 one more (down -> up). t7 wrong again: the
// counter (reset to 0 by the step) goes to -1, same direction, no reversal. t10 is the 4th
// reversal and the 11th trial: finished.
TEST(Staircase, LinearWithInitialRuleAndStepList) {
  StaircaseSpec spec;
  spec.start_value = 10;
  spec.step_sizes = {4, 2, 1};
  spec.step_type = StepType::lin;
  spec.n_up = 1;
  spec.n_down = 3;
  spec.n_reversals = 4;
  spec.n_trials = 10;
  Staircase staircase(spec);
  for (int r : {1, 1, 0, 1, 1, 1, 0, 0, 1, 1, 1}) {
    ASSERT_FALSE(staircase.finished());
    staircase.add_response(r == 1);
  }
  EXPECT_TRUE(staircase.finished());
  expect_doubles(staircase.intensities(), {10, 6, 2, 4, 4, 4, 3, 4, 5, 5, 5});
  EXPECT_EQ(staircase.reversal_trials(), (std::vector<int>{2, 5, 6, 10}));
  expect_doubles(staircase.reversal_intensities(), {2, 4, 3, 5});
  EXPECT_DOUBLE_EQ(staircase.next_intensity(), 4);
  EXPECT_DOUBLE_EQ(staircase.mean_of_last_reversals(3), (4.0 + 3.0 + 5.0) / 3.0);
  EXPECT_DOUBLE_EQ(staircase.mean_of_last_reversals(10), (2.0 + 4.0 + 3.0 + 5.0) / 4.0);
  EXPECT_THROW(staircase.add_response(true), std::logic_error);
}

// The same responses with and without the initial rule (lin, step 2, 1-up/2-down).
// Without it, t1's wrong answer goes up from direction 'start': no reversal; the first reversal
// is t3 (two rights after going up).
TEST(Staircase, WithoutInitialRuleNUpMDownFromTheFirstTrial) {
  StaircaseSpec spec;
  spec.start_value = 10;
  spec.step_sizes = {2};
  spec.step_type = StepType::lin;
  spec.n_up = 1;
  spec.n_down = 2;
  spec.n_reversals = 3;
  spec.apply_initial_rule = false;
  const StairRun without = run(spec, {1, 0, 1, 1, 1, 1, 0, 0, 1, 1, 1, 1});
  expect_doubles(without.intensities, {10, 10, 12, 12, 10, 10, 8, 10, 12, 12});
  EXPECT_EQ(without.reversal_trials, (std::vector<int>{3, 6, 9}));
  expect_doubles(without.reversal_intensities, {12, 8, 12});

  // With the rule: t0 steps down at once (1-down), t1's wrong answer is the first reversal.
  spec.apply_initial_rule = true;
  const StairRun with = run(spec, {1, 0, 1, 1, 1, 1, 0, 0, 1, 1, 1, 1});
  expect_doubles(with.intensities, {10, 8, 10, 10, 8, 8, 6});
  EXPECT_EQ(with.reversal_trials, (std::vector<int>{1, 3, 6}));
  expect_doubles(with.reversal_intensities, {8, 10, 6});
}

// db steps of 20 dB (x or / 10 exactly), 1-up/1-down, min 1 and max 500. t2 steps 1 -> 0.1,
// clamped to 1; t5 steps 100 -> 1000, clamped to 500, and the next decrement starts from 500.
TEST(Staircase, DecibelStepsWithClamping) {
  StaircaseSpec spec;
  spec.start_value = 100;
  spec.step_sizes = {20};
  spec.step_type = StepType::db;
  spec.n_up = 1;
  spec.n_down = 1;
  spec.n_reversals = 3;
  spec.min_value = 1;
  spec.max_value = 500;
  const StairRun r = run(spec, {1, 1, 1, 0, 0, 0, 1, 1, 0, 1});
  expect_doubles(r.intensities, {100, 10, 1, 1, 10, 100, 500, 50, 5});
  EXPECT_EQ(r.reversal_trials, (std::vector<int>{3, 6, 8}));
  expect_doubles(r.reversal_intensities, {1, 500, 5});
}

// A 6 dB step multiplies by 10^(6/20) = 1.99526231496888 (not 2).
TEST(Staircase, DecibelStepFactor) {
  StaircaseSpec spec;
  spec.start_value = 1;
  spec.step_sizes = {6};
  spec.n_reversals = 1;
  spec.n_down = 1;
  Staircase staircase(spec);
  staircase.add_response(false);
  EXPECT_NEAR(staircase.next_intensity(), 1.99526231496888, 1e-13);
  staircase.add_response(true);  // reversal; down by the same factor
  EXPECT_NEAR(staircase.next_intensity(), 1.0, 1e-15);
}

// log steps 2 then 1 (x or / 100, then 10), 1-up/2-down; the last step size is reused after the
// list runs out, and reaching 2 reversals at t3 does not finish before 8 trials.
TEST(Staircase, LogStepsLastSizeReusedAndTrialMinimum) {
  StaircaseSpec spec;
  spec.start_value = 1;
  spec.step_sizes = {2, 1};
  spec.step_type = StepType::log;
  spec.n_up = 1;
  spec.n_down = 2;
  spec.n_reversals = 2;
  spec.n_trials = 8;
  const StairRun r = run(spec, {1, 0, 1, 1, 0, 1, 1, 1, 1, 1});
  EXPECT_EQ(r.trials, 8);
  expect_doubles(r.intensities, {1, 0.01, 0.1, 0.1, 0.01, 0.1, 0.1, 0.01});
  EXPECT_EQ(r.reversal_trials, (std::vector<int>{1, 3, 4, 6}));
  expect_doubles(r.reversal_intensities, {0.01, 0.1, 0.01, 0.1});
}

TEST(Staircase, RefusesStepListLongerThanReversalCount) {
  StaircaseSpec spec;
  spec.step_sizes = {8, 4, 2};
  spec.n_reversals = 2;
  EXPECT_THROW(Staircase{spec}, std::invalid_argument);
  spec.n_reversals = 3;
  EXPECT_NO_THROW(Staircase{spec});
  spec.start_value = 0;  // db cannot start at 0
  EXPECT_THROW(Staircase{spec}, std::invalid_argument);
  EXPECT_THROW(parse_step_type("dB"), std::invalid_argument);
}

// Interleaving: every pass runs each unfinished staircase exactly once, in a seeded order that
// differs between passes and reproduces with the seed.
TEST(InterleavedStaircases, EachPassIsAPermutationAndSeedReproducesIt) {
  auto make_specs = [] {
    std::vector<StaircaseSpec> specs(4);
    for (std::size_t i = 0; i < specs.size(); ++i) {
      specs[i].name = "s" + std::to_string(i);
      specs[i].n_reversals = 1;
      specs[i].n_trials = static_cast<int>(3 + i);  // finish after 3, 4, 5, 6 trials
    }
    return specs;
  };
  auto order_for = [&](std::uint64_t seed) {
    InterleavedStaircases stairs(make_specs(), seed);
    std::vector<std::size_t> order;
    while (auto next = stairs.next()) {
      order.push_back(*next);
      // A wrong answer after a right one reverses once; afterwards only the trial count matters.
      stairs.at(*next).add_response(stairs.at(*next).trial_count() != 1);
    }
    return order;
  };
  const auto order = order_for(42);
  EXPECT_EQ(order, order_for(42));
  EXPECT_NE(order, order_for(43));
  ASSERT_EQ(order.size(), 3u + 4u + 5u + 6u);
  // Passes 1-3 hold all four staircases; pass 4 the three left, then two, then one.
  const std::vector<std::size_t> pass_sizes = {4, 4, 4, 3, 2, 1};
  std::size_t at = 0;
  std::set<std::vector<std::size_t>> distinct_orders;
  for (std::size_t size : pass_sizes) {
    std::vector<std::size_t> pass(order.begin() + static_cast<long>(at), order.begin() + static_cast<long>(at + size));
    std::set<std::size_t> unique(pass.begin(), pass.end());
    EXPECT_EQ(unique.size(), size);
    if (size == 4) distinct_orders.insert(pass);
    at += size;
  }
  EXPECT_GT(distinct_orders.size(), 1u);
}

}  // namespace
}  // namespace glarelab
