// The straylight measurement as a procedure: levels and sides from the seeded generator, answers
// scored against the compensated side, a replay of the stored responses reaching the same trials,
// and the display's glow subtracted from the estimate (docs/STRAYLIGHT.md).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "protocols/straylight_observer.h"
#include "protocols/straylight_procedure.h"

namespace glarelab {
namespace {

StraylightSpec clinic_ring(double glow_cd_m2 = 0.0) {
  StraylightSpec spec;
  spec.eye = "right";
  spec.ring_luminance_cd_m2 = 200.0;
  spec.display_glow_cd_m2 = glow_cd_m2;
  return spec;
}

// An eye whose s is `log_s` at every angle of the ring: its veil is k s L_ring.
StraylightObserver eye_with(double log_s, std::uint64_t seed) {
  StraylightObserverEye eye;
  eye.ring_veil_fraction = ring_straylight_constant(5.0, 10.0) * std::pow(10.0, log_s);
  return StraylightObserver(eye, seed);
}

struct Measurement {
  std::vector<TrialPlan> plans;
  std::vector<std::string> responses;
  StraylightEstimate estimate;
};

// The whole measurement: the observer sees the ring, the display's glow and the compensation on
// the plan's side, and answers with the half it sees flicker more.
Measurement measure(const StraylightSpec& spec, double true_log_s, double glow_seen_cd_m2, std::uint64_t seed) {
  StraylightProcedure procedure(spec, seed);
  const StraylightObserver observer = eye_with(true_log_s, seed + 1000);
  Measurement run;
  while (!procedure.finished()) {
    const TrialPlan plan = procedure.next_trial();
    const bool left = plan.condition_json.find("\"compensated_side\":\"left\"") != std::string::npos;
    const double level_cd_m2 = ring_straylight_constant(5.0, 10.0) * std::pow(10.0, *plan.intensity) * spec.ring_luminance_cd_m2;
    const bool stronger = observer.compensated_stronger(
        {spec.ring_luminance_cd_m2, glow_seen_cd_m2, level_cd_m2}, static_cast<std::uint64_t>(plan.trial_index));
    const std::string answer = stronger == left ? "left" : "right";
    procedure.record_response(plan, {answer, 0.8});
    run.plans.push_back(plan);
    run.responses.push_back(answer);
  }
  run.estimate = procedure.estimate();
  return run;
}

TEST(StraylightProcedure, RunsItsAnswersOnTheCompensationRangeWithSeededSides) {
  const std::uint64_t seed = 11;
  const Measurement run = measure(clinic_ring(), 1.1, 0.0, seed);
  ASSERT_EQ(run.plans.size(), 25u);
  int left = 0;
  for (std::size_t i = 0; i < run.plans.size(); ++i) {
    const TrialPlan& plan = run.plans[i];
    EXPECT_EQ(plan.trial_index, static_cast<int>(i));
    EXPECT_EQ(plan.procedure, "straylight");
    EXPECT_EQ(plan.allowed_responses, (std::vector<std::string>{"left", "right"}));
    EXPECT_TRUE(plan.correct_response.empty());
    ASSERT_TRUE(plan.intensity);
    EXPECT_GE(*plan.intensity, kStraylightMinCompensationLog10);
    EXPECT_LE(*plan.intensity, kStraylightMaxCompensationLog10);
    // Every level lies on the 0.02 log10 grid the display was checked to resolve.
    EXPECT_NEAR(*plan.intensity / 0.02, std::round(*plan.intensity / 0.02), 1e-6) << *plan.intensity;
    const bool on_left = compensation_on_left(seed, i);
    left += on_left;
    EXPECT_NE(plan.condition_json.find(on_left ? "\"compensated_side\":\"left\"" : "\"compensated_side\":\"right\""),
              std::string::npos);
  }
  // The range finding starts above any eye (2.1) and steps by 0.2.
  EXPECT_NEAR(*run.plans[0].intensity, 2.1, 1e-12);
  EXPECT_NEAR(std::abs(*run.plans[1].intensity - 2.1), 0.2, 1e-9);
  EXPECT_GT(left, 5);
  EXPECT_LT(left, 20);
}

TEST(StraylightProcedure, AReplayOfTheStoredResponsesReachesTheSameTrials) {
  const Measurement run = measure(clinic_ring(), 1.3, 0.0, 5);
  StraylightProcedure replay(clinic_ring(), 5);
  for (std::size_t i = 0; i < run.plans.size(); ++i) {
    const TrialPlan plan = replay.next_trial();
    EXPECT_EQ(*plan.intensity, *run.plans[i].intensity);
    EXPECT_EQ(plan.condition_json, run.plans[i].condition_json);
    replay.record_response(plan, {run.responses[i], std::nullopt});
  }
  EXPECT_TRUE(replay.finished());
  EXPECT_EQ(replay.estimate().log_s, run.estimate.log_s);
}

TEST(StraylightProcedure, ATimeoutDrawsAFreshSideAndAnAbortChangesNothing) {
  StraylightProcedure procedure(clinic_ring(), 3);
  const TrialPlan first = procedure.next_trial();
  procedure.record_response(first, {"abort", std::nullopt});
  EXPECT_EQ(procedure.next_trial().condition_json, first.condition_json);
  procedure.record_response(first, {"timeout", std::nullopt});
  EXPECT_TRUE(procedure.answers().empty());
  const TrialPlan second = procedure.next_trial();
  EXPECT_EQ(second.trial_index, 1);
  EXPECT_EQ(*second.intensity, *first.intensity);  // no answer: the range finding has not moved
  procedure.record_response(second, {compensation_on_left(3, 1) ? "left" : "right", 0.5});
  ASSERT_EQ(procedure.answers().size(), 1u);
  EXPECT_TRUE(procedure.answers()[0].compensated_stronger);
}

TEST(StraylightProcedure, RecoversTheEyeAndSubtractsTheDisplaysGlow) {
  // 0.8 cd/m2 of glow around a 200 cd/m2 ring is 0.8 / (1.327e-3 x 200) = 3.0 deg^2/sr (the most
  // the configuration accepts is 10^0.6 = 4.0): with an eye of log s 0.9 (7.9) the answers see
  // log10(10.9) = 1.04.
  const double glow_cd_m2 = 0.8;
  const double glow_straylight = glow_cd_m2 / (ring_straylight_constant(5.0, 10.0) * 200.0);
  EXPECT_NEAR(std::log10(std::pow(10.0, 0.9) + glow_straylight), 1.04, 0.005);
  double subtracted = 0.0, ignored = 0.0, plain = 0.0;
  const int seeds = 20;
  for (int seed = 0; seed < seeds; ++seed) {
    subtracted += measure(clinic_ring(glow_cd_m2), 0.9, glow_cd_m2, static_cast<std::uint64_t>(seed)).estimate.log_s;
    ignored += measure(clinic_ring(0.0), 0.9, glow_cd_m2, static_cast<std::uint64_t>(seed)).estimate.log_s;
    plain += measure(clinic_ring(0.0), 0.9, 0.0, static_cast<std::uint64_t>(seed)).estimate.log_s;
  }
  EXPECT_NEAR(plain / seeds, 0.9, 0.03);
  EXPECT_NEAR(subtracted / seeds, 0.9, 0.04);
  EXPECT_NEAR(ignored / seeds, 1.04, 0.04);
}

}  // namespace
}  // namespace glarelab
