// Timing and tracker quality of a database against hand-counted values: dropped frames, onset
// jitter, frame intervals and response times; valid samples, blinks (invalid runs of 50-500 ms)
// and the onset-aligned pupil trace.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/loaded_database.h"
#include "analysis/timing_quality.h"
#include "analysis/tracker_quality.h"
#include "tests/analysis_synthetic.h"
#include "tests/scratch_dir.h"

namespace glarelab::analysis {
namespace {

TrialRecord trial_at(std::int64_t session_id, int index, double onset_s, double response_time_s) {
  TrialRecord trial;
  trial.session_id = session_id;
  trial.trial_index = index;
  trial.procedure = "forced_choice";
  trial.condition = "{\"name\":\"a\"}";
  trial.response = "left";
  trial.onset_s = onset_s;
  trial.response_time_s = response_time_s;
  trial.started_utc = "2026-01-01T00:00:00.000Z";
  return trial;
}

FrameRecord frame_at(int index, double scheduled_s, double flip_s, bool dropped = false) {
  FrameRecord frame;
  frame.frame_index = index;
  frame.scheduled_s = scheduled_s;
  frame.flip_s = flip_s;
  frame.dropped = dropped;
  return frame;
}

TEST(AnalysisQuality, TimingCountsDropsJitterIntervalsAndResponseTimes) {
  const test::ScratchDir dir;
  const std::string path = dir.file("timing.db");
  {
    ResultStore store(path);
    const auto id = store.begin_session(test::synthetic_session("P"));
    const double period_s = 0.01;
    // Trial 0: onset flip 2 ms late; intervals 10, 10 ms.
    store.commit_trial(trial_at(id, 0, 1.002, 0.5),
                       {frame_at(0, 1.0, 1.002), frame_at(1, 1.01, 1.012), frame_at(2, 1.02, 1.022)});
    // Trial 1: onset 1 ms early; the third flip came 20 ms after the second (one refresh lost).
    store.commit_trial(trial_at(id, 1, 2.999, 0.7),
                       {frame_at(0, 3.0, 2.999), frame_at(1, 3.01, 3.009), frame_at(2, 3.02, 3.029, true)});
    // Trial 2: on time; intervals 10 ms.
    store.commit_trial(trial_at(id, 2, 5.0, 0.9), {frame_at(0, 5.0, 5.0), frame_at(1, 5.0 + period_s, 5.01)});
    store.finish_session(id, "completed");
  }
  const TimingQuality quality = analyse_timing(load_databases({path}));
  ASSERT_EQ(quality.sessions.size(), 1u);
  const SessionTiming& timing = quality.sessions[0];
  EXPECT_EQ(timing.trials, 3);
  EXPECT_EQ(timing.frames, 8);
  EXPECT_EQ(timing.dropped, 1);
  // Onset errors +2, -1, 0 ms: mean 1/3 ms, sample SD sqrt(((5/3)^2 + (4/3)^2 + (1/3)^2) / 2) ms.
  ASSERT_TRUE(timing.onset_jitter_sd_s.has_value());
  EXPECT_NEAR(*timing.onset_jitter_sd_s, 1e-3 * std::sqrt((25.0 + 16.0 + 1.0) / 9.0 / 2.0), 1e-12);
  EXPECT_NEAR(*timing.onset_jitter_max_abs_s, 0.002, 1e-12);
  // Intervals within trials: 10, 10 | 10, 20 | 10 ms: mean 12 ms, SD sqrt((4*4 + 64) / 4) ms.
  EXPECT_NEAR(*timing.frame_interval_mean_s, 0.012, 1e-12);
  EXPECT_NEAR(*timing.frame_interval_sd_s, 1e-3 * std::sqrt(80.0 / 4.0), 1e-12);
  EXPECT_NEAR(*quality.response_time_median_s, 0.7, 1e-15);
  EXPECT_NEAR(*quality.response_time_mean_s, 0.7, 1e-15);
}

// Eye 0 at 100 Hz over 4 s (t = 0.005 + 0.01 i), invalid runs: i 0-4 (leading: no valid sample
// before it), 50-52 (30 ms + one period = 40 ms gap: a dropout), 100-108 (100 ms gap: blink),
// 130-159 (310 ms: blink), 230-239 (110 ms: blink), 300-359 (610 ms: lost tracking), 395-399
// (trailing). Eye 1 until 1.4 s with one invalid run i 60-79 (210 ms: blink). Pupil 4 mm before
// the trial's onset at 2 s, 5 mm from it.
TEST(AnalysisQuality, TrackerCountsValidSamplesBlinksAndAlignsThePupilToOnset) {
  const test::ScratchDir dir;
  const std::string path = dir.file("tracker.db");
  const auto invalid_eye0 = [](int i) {
    return i <= 4 || (i >= 50 && i <= 52) || (i >= 100 && i <= 108) || (i >= 130 && i <= 159) ||
           (i >= 230 && i <= 239) || (i >= 300 && i <= 359) || i >= 395;
  };
  {
    ResultStore store(path);
    const auto id = store.begin_session(test::synthetic_session("P"));
    std::vector<TrackerSampleRecord> samples;
    for (int i = 0; i < 400; ++i) {
      TrackerSampleRecord sample;
      sample.eye = 0;
      sample.session_time_s = 0.005 + 0.01 * i;
      sample.device_time_s = sample.session_time_s + 100.0;
      sample.valid = !invalid_eye0(i);
      if (sample.valid) sample.pupil_diameter_mm = sample.session_time_s < 2.0 ? 4.0 : 5.0;
      sample.confidence = sample.valid ? 0.95 : 0.0;
      samples.push_back(sample);
      if (i < 140) {
        TrackerSampleRecord other = sample;
        other.eye = 1;
        other.valid = !(i >= 60 && i <= 79);
        other.pupil_diameter_mm = other.valid ? std::optional<double>(6.0) : std::nullopt;
        samples.push_back(other);
      }
    }
    store.append_tracker_samples(id, samples);
    store.commit_trial(trial_at(id, 0, 2.0, 0.5), {frame_at(0, 2.0, 2.0)});
    store.finish_session(id, "completed");
  }
  const TrackerQuality quality = analyse_tracker(load_databases({path}));
  ASSERT_EQ(quality.sessions.size(), 1u);
  const SessionTracker& tracker = quality.sessions[0];
  EXPECT_EQ(tracker.samples, 540);
  EXPECT_EQ(tracker.valid, 278 + 120);
  EXPECT_EQ(tracker.blinks, 3 + 1);
  // Bins of 50 ms from -0.5 s: 0-1 empty (invalid), 2-9 at 4 mm, 10-15 at 5 mm, 16-17 empty,
  // 18-29 at 5 mm, 30-41 empty (lost tracking), 42-48 at 5 mm, 49 empty (trailing run).
  const PupilTrace& trace = tracker.pupil;
  ASSERT_EQ(trace.pupil_diameter_mm.size(), 50u);
  EXPECT_NEAR(trace.time_from_onset_s[0], -0.475, 1e-12);
  for (std::size_t bin = 0; bin < 50; ++bin) {
    const bool empty = bin <= 1 || bin == 16 || bin == 17 || (bin >= 30 && bin <= 41) || bin == 49;
    if (empty) {
      EXPECT_FALSE(trace.pupil_diameter_mm[bin].has_value()) << "bin " << bin;
    } else {
      ASSERT_TRUE(trace.pupil_diameter_mm[bin].has_value()) << "bin " << bin;
      EXPECT_DOUBLE_EQ(*trace.pupil_diameter_mm[bin], bin < 10 ? 4.0 : 5.0) << "bin " << bin;
    }
  }
}

}  // namespace
}  // namespace glarelab::analysis
