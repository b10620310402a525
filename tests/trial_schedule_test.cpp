// The flip-by-flip schedule of a trial (runner/session/trial_schedule.h), the refresh-rate check,
// timeouts in the procedures, and the phase summary written to the session log.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/timing_quality.h"
#include "protocols/adaptive_procedure.h"
#include "protocols/fixed_design_procedure.h"
#include "runner/session/refresh_rate_check.h"
#include "runner/session/trial_schedule.h"
#include "stimuli/display_model.h"

namespace glarelab {
namespace {

TrialPlan plan_with(int trial_index, int stimulus_frames, const std::string& screen_text = "") {
  TrialPlan plan;
  plan.trial_index = trial_index;
  plan.stimulus_frames = stimulus_frames;
  plan.screen_text = screen_text;
  return plan;
}

std::string phases_of(const TrialSchedule& schedule) {
  std::string text;
  for (const TimedFlip& flip : schedule.timed) {
    if (flip.phase == FlipPhase::fixation) text += "F";
    if (flip.phase == FlipPhase::inter_stimulus) text += "-";
    if (flip.phase == FlipPhase::interval) text += std::to_string(flip.stimulus_frame);
  }
  return text;
}

TEST(TrialSchedule, SideBySideTrialIsFixationThenStimulus) {
  PresentationSpec spec;
  spec.fixation.frames = 3;
  spec.inter_stimulus.frames = 2;
  const TrialSchedule schedule = schedule_trial(spec, plan_with(0, 4), false);
  EXPECT_EQ(phases_of(schedule), "FFF0123");
  EXPECT_EQ(schedule.intervals, 1);
  EXPECT_EQ(schedule.onset_flip, 3u);
  EXPECT_EQ(schedule.first_answer_flip, 3u);
  EXPECT_EQ(schedule.inter_trial_frames, 0) << "nothing precedes the session's first trial";
  EXPECT_EQ(schedule_trial(spec, plan_with(1, 4), false).inter_trial_frames, 2);
}

TEST(TrialSchedule, SequentialTrialHasTwoIntervalsAroundTheInterStimulusInterval) {
  PresentationSpec spec;
  spec.fixation.frames = 2;
  spec.inter_stimulus.frames = 3;
  const TrialSchedule schedule = schedule_trial(spec, plan_with(5, 2), true);
  EXPECT_EQ(phases_of(schedule), "FF01---23");
  EXPECT_EQ(schedule.intervals, 2);
  EXPECT_EQ(schedule.onset_flip, 2u);
  EXPECT_EQ(schedule.first_answer_flip, 7u) << "answers count from the second interval's onset";
  EXPECT_EQ(schedule.timed[7].interval, 1);
  EXPECT_EQ(schedule.timed[7].frame_in_interval, 0);
}

TEST(TrialSchedule, ScreensComeInstructionsBreakThenBlockText) {
  PresentationSpec spec;
  spec.instructions = "Welcome";
  spec.break_every_trials = 3;
  spec.break_text = "Rest";
  const auto kinds = [&](const TrialPlan& plan) {
    std::string text;
    for (const ScreenText& screen : schedule_trial(spec, plan, false).screens) text += screen.kind + ":" + screen.text + " ";
    return text;
  };
  EXPECT_EQ(kinds(plan_with(0, 1, "Block A")), "instructions:Welcome block:Block A ");
  EXPECT_EQ(kinds(plan_with(1, 1)), "");
  EXPECT_EQ(kinds(plan_with(3, 1)), "break:Rest ");
  EXPECT_EQ(kinds(plan_with(6, 1, "Block B")), "break:Rest block:Block B ");
}

TEST(TrialSchedule, PhaseSummaryNamesRunsOfFlips) {
  std::vector<PhaseFlip> flips = {{FlipPhase::inter_trial}, {FlipPhase::screen}, {FlipPhase::fixation},
                                  {FlipPhase::interval, 0, 0}, {FlipPhase::interval, 0, 1},
                                  {FlipPhase::inter_stimulus}, {FlipPhase::interval, 1, 2},
                                  {FlipPhase::interval, 1, 3}, {FlipPhase::response}, {FlipPhase::feedback},
                                  {FlipPhase::feedback}};
  EXPECT_EQ(describe_trial_phases(4, flips),
            "trial 4: inter-trial 1, screen 1, fixation 1, interval 1 2 (frames 0-1), inter-stimulus 1, "
            "interval 2 2 (frames 2-3), response 1, feedback 2 flips");
  EXPECT_EQ(first_words("Which   light\nis brighter?", 8), "Which light is brighter?");
  EXPECT_EQ(first_words("one two three four", 2), "one two ...");
}

TEST(RefreshRateCheck, WarnsAboveOnePercent) {
  EXPECT_EQ(refresh_rate_warning(60.0, 60.0), "");
  EXPECT_EQ(refresh_rate_warning(60.0, 59.94), "");  // NTSC-style 59.94 Hz: 0.1 %
  EXPECT_EQ(refresh_rate_warning(60.0, 60.59), "");  // just under 1 %
  EXPECT_EQ(refresh_rate_warning(60.0, 75.0),
            "the display refreshes at 75 Hz, not the experiment's refresh_hz 60 Hz ([display]): durations counted in "
            "frames last 0.8 times as long as planned");
  EXPECT_NE(refresh_rate_warning(120.0, 118.0), "");  // 1.7 %
}

TEST(DisplayGeometry, PixelsForDegreesInvertsDegreesForPixels) {
  DisplaySpec spec;
  spec.viewing_distance_mm = 600.0;
  spec.pixel_pitch_mm = 0.25;
  const DisplayModel display(spec);
  // 1 degree at 600 mm: 2 x 600 x tan(0.5 deg) = 1200 x 0.00872687 = 10.47224 mm = 41.88897 px of 0.25 mm.
  EXPECT_NEAR(display.pixels_for_centred_span(1.0), 41.88897, 1e-4);
  for (double degrees : {0.1, 0.6, 5.0, 30.0})
    EXPECT_NEAR(display.degrees_for_centred_span(display.pixels_for_centred_span(degrees)), degrees, 1e-12);
}

TEST(ProcedureTimeout, FixedDesignMovesOnWithoutScoring) {
  TrialPlan first = plan_with(0, 1);
  first.allowed_responses = {"left", "right"};
  first.correct_response = "left";
  TrialPlan second = first;
  second.trial_index = 1;
  FixedDesignProcedure procedure({first, second}, [](const TrialPlan&, const Response& response) {
    TrialOutcome outcome;
    outcome.response = response.value;
    return outcome;
  });
  const TrialOutcome outcome = procedure.record_response(procedure.next_trial(), Response{kTimeoutResponse, std::nullopt});
  EXPECT_EQ(outcome.response, "timeout");
  EXPECT_EQ(procedure.next_trial().trial_index, 1);
}

TEST(ProcedureTimeout, StaircaseRepeatsTheIntensityAfterATimeout) {
  Experiment experiment;
  experiment.procedure = "staircase";
  ConditionRow row;
  row.fields = {{"name", "r"}, {"reference", "ref"}, {"comparison", "cmp"}};
  row.number = 1;
  experiment.conditions = {row};
  AdaptiveTrackSpec track;
  track.staircase.start_value = 100.0;
  track.staircase.step_sizes = {4.0};
  track.staircase.n_reversals = 2;
  experiment.adaptive.tracks = {track};
  AdaptiveProcedure procedure(experiment, {{"ref", 50.0}, {"cmp", 10.0}});
  const TrialPlan first = procedure.next_trial();
  const TrialOutcome timeout = procedure.record_response(first, Response{kTimeoutResponse, std::nullopt});
  EXPECT_FALSE(timeout.correct.has_value()) << "a timeout is never scored";
  EXPECT_FALSE(timeout.reversal.has_value());
  const TrialPlan second = procedure.next_trial();
  EXPECT_EQ(second.trial_index, 1);
  EXPECT_EQ(second.intensity, first.intensity) << "the track did not move";
  EXPECT_EQ(procedure.staircase(0)->trial_count(), 0);
  // An answer moves it: correct (100 > 50) -> down by 4 dB under the initial 1-up/1-down rule.
  procedure.record_response(second, Response{second.correct_response, 0.5});
  EXPECT_NEAR(*procedure.next_trial().intensity, 100.0 / std::pow(10.0, 4.0 / 20.0), 1e-9);
}

// Timing quality over a trial with other flips around its stimulus frames (frame_index < 0):
// stimulus frames are counted alone, the onset is frame 0, intervals run over every flip.
TEST(TimingQualityWithPhases, StimulusFramesAloneAreCountedAndFrameZeroIsTheOnset) {
  analysis::LoadedData data;
  data.sessions.emplace_back();
  data.sessions[0].trials.emplace_back();
  // Flip order: fixation -1 -2, stimulus 0 1 (frame 0 scheduled 1 ms early), feedback -3 (late).
  data.sessions[0].trials[0].frames = {{-1, 0.0, 0.0, false, {}},
                                       {-2, 0.01, 0.01, false, {}},
                                       {0, 0.019, 0.02, false, {}},
                                       {1, 0.03, 0.03, false, {}},
                                       {-3, 0.06, 0.06, true, {}}};
  const analysis::TimingQuality quality = analysis::analyse_timing(data);
  ASSERT_EQ(quality.sessions.size(), 1u);
  const analysis::SessionTiming& timing = quality.sessions[0];
  EXPECT_EQ(timing.frames, 2);
  EXPECT_EQ(timing.dropped, 1);
  ASSERT_TRUE(timing.onset_jitter_max_abs_s.has_value());
  EXPECT_NEAR(*timing.onset_jitter_max_abs_s, 0.001, 1e-12);
  // Intervals 0.01, 0.01, 0.01, 0.03: mean 0.015.
  ASSERT_TRUE(timing.frame_interval_mean_s.has_value());
  EXPECT_NEAR(*timing.frame_interval_mean_s, 0.015, 1e-12);
}

}  // namespace
}  // namespace glarelab
