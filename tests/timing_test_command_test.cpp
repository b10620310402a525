// `glarelab timing-test` offscreen on the virtual clock: every flip at k / refresh_hz exactly, so
// the reported figures are the nominal period with SD 0 and no missed deadline; the session, its
// trial of procedure timing_test and every flip land in the database, with the display's info
// dump, and `glarelab analyze` shows them in its timing table. The patterns are checked pixel by
// pixel against their definition, the statistics against hand-worked values.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_process.h"
#include "runner/calibration/patch_drawing.h"
#include "runner/display/display_backend.h"
#include "runner/store/result_store.h"
#include "runner/timing/flip_statistics.h"
#include "runner/timing/timing_pattern.h"
#include "scratch_dir.h"
#include "session_events.h"

namespace glarelab {
namespace {

TEST(TimingTestCommand, OffscreenVirtualClockReportsTheExactNominalPeriodAndTheSessionReachesAnalyze) {
  const test::ScratchDir dir;
  const std::string db = dir.file("rig.db");
  const int frames = 120;
  const auto run = test::run_glarelab({"timing-test", "--display", "offscreen", "--frames", std::to_string(frames),
                                       "--refresh-hz", "75", "--width", "64", "--height", "48", "--db", db},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // 1 / 75 s = 13.333333 ms; the virtual clock stamps flip k at k / 75 s, so every interval is the
  // period to double rounding: SD 0 and no late flip.
  EXPECT_THAT(run.output, ::testing::HasSubstr("flip interval mean 13.333333 ms (nominal 13.333333 ms, +0.000000 ms), "
                                               "SD 0.000000 ms, min 13.333333 ms, max 13.333333 ms"));
  EXPECT_THAT(run.output, ::testing::HasSubstr("missed deadlines 0 (interval > 1.5 periods)"));

  const ResultStore store(db);
  const auto sessions = store.load_sessions();
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].experiment, "timing-test");
  EXPECT_EQ(sessions[0].status, "completed");
  EXPECT_EQ(sessions[0].clock, "virtual");
  EXPECT_EQ(sessions[0].display_backend, "offscreen");
  const auto trials = store.load_trials(sessions[0].id);
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].procedure, "timing_test");
  EXPECT_EQ(trials[0].condition, R"({"name":"timing_test","pattern":"flicker","frames":"120"})");
  const auto flips = store.load_frames(trials[0].id);
  ASSERT_EQ(flips.size(), static_cast<std::size_t>(frames));
  for (int k = 0; k < frames; ++k) {
    const FrameRecord& flip = flips[static_cast<std::size_t>(k)];
    EXPECT_EQ(flip.frame_index, k);
    EXPECT_NEAR(flip.flip_s, k / 75.0, 1e-12) << k;
    EXPECT_NEAR(flip.scheduled_s, k / 75.0, 1e-12) << k;
    EXPECT_FALSE(flip.dropped) << k;
  }
  const auto figures = test::session_event_messages(store, "timing_test");
  ASSERT_EQ(figures.size(), 1u);
  EXPECT_THAT(figures[0], ::testing::HasSubstr("120 frames; flip interval mean 13.333333 ms"));
  EXPECT_THAT(figures[0], ::testing::HasSubstr("loop overhead p50 "));
  // The info dump every session carries (runner/display/display_info.h).
  const auto display = test::session_event_messages(store, "display");
  ASSERT_EQ(display.size(), 1u);
  for (const char* fact : {"backend offscreen 64x48", "mode offscreen 64x48, no monitor", "refresh 75 Hz (virtual)",
                           "; framebuffer ", " bits; GL renderer ", "; GL vendor ", "; GL version (driver) 4.",
                           "; GLSL 4.", "; clock virtual"})
    EXPECT_THAT(display[0], ::testing::HasSubstr(fact));
  EXPECT_EQ(test::session_event_messages(store, "frame_timing").size(), 1u);

  // analyze's timing table: 120 frames, none dropped, intervals 13.333 +/- 0.000 ms.
  const auto analysed = test::run_glarelab({"analyze", db, "--out", dir.file("report")}, dir.path());
  ASSERT_EQ(analysed.exit_code, 0) << analysed.output;
  EXPECT_THAT(analysed.output, ::testing::HasSubstr("timing: 120 frames, 0 dropped"));
  EXPECT_THAT(test::read_bytes(dir.file("report/report.html")),
              ::testing::HasSubstr("<td>120</td><td>0 (0.00%)</td><td>0.000</td><td>0.000</td><td>13.333 +/- 0.000</td>"));
}

TEST(TimingTestCommand, BadOptionsAreRefusedBeforeTheDatabaseIsCreated) {
  const test::ScratchDir dir;
  const std::string db = dir.file("rig.db");
  for (const std::vector<std::string>& options :
       {std::vector<std::string>{"--frames", "1"}, {"--frames", "-5"}, {"--pattern", "stripes"}, {"--refresh-hz", "0"}}) {
    std::vector<std::string> arguments = {"timing-test", "--display", "offscreen", "--db", db};
    arguments.insert(arguments.end(), options.begin(), options.end());
    const auto run = test::run_glarelab(arguments, dir.path());
    EXPECT_EQ(run.exit_code, 2) << options[0] << " " << options[1] << "\n" << run.output;
    EXPECT_FALSE(std::filesystem::exists(db)) << options[0] << " " << options[1];
  }
}

// Reads back what draw_timing_pattern drew into an offscreen default framebuffer.
ImageRGBA drawn(TimingPattern pattern, long frame, int width_px, int height_px, DisplayBackend& display) {
  draw_timing_pattern(pattern, frame, width_px, height_px);
  const ImageRGBA image = read_default_framebuffer(width_px, height_px);
  display.present();
  return image;
}

TEST(TimingTestPattern, FlickerAlternatesWhiteAndBlackAndTearingBarsMoveAFourthOfTheirWidthPerFrame) {
  DisplayRequest request;
  request.width_px = 64;
  request.height_px = 8;
  const auto display = create_display("offscreen", request);
  // Flicker: white on even frames (the first flip is a white edge for the photodiode), black on odd.
  for (long frame : {0L, 1L, 2L, 7L}) {
    const ImageRGBA image = drawn(TimingPattern::flicker, frame, 64, 8, *display);
    const float expected = frame % 2 == 0 ? 1.0f : 0.0f;
    for (int x : {0, 31, 63}) EXPECT_EQ(image.pixel(x, 4)[0], expected) << "frame " << frame << " x " << x;
  }
  // Tearing at 64 px: bars 4 px wide every 8 px, moving 1 px per frame; frame 3 has bars at
  // x = 3..6, 11..14, ..., 59..62 and frame 8 is frame 0 again (hand-worked from the fractions).
  EXPECT_THAT(tearing_bar_lefts_px(64, 0), ::testing::ElementsAre(0, 8, 16, 24, 32, 40, 48, 56));
  EXPECT_THAT(tearing_bar_lefts_px(64, 3), ::testing::ElementsAre(3, 11, 19, 27, 35, 43, 51, 59));
  EXPECT_THAT(tearing_bar_lefts_px(64, 6), ::testing::ElementsAre(-2, 6, 14, 22, 30, 38, 46, 54, 62));
  EXPECT_EQ(tearing_bar_lefts_px(64, 8), tearing_bar_lefts_px(64, 0));
  const ImageRGBA frame3 = drawn(TimingPattern::tearing, 3, 64, 8, *display);
  for (int x = 0; x < 64; ++x) {
    const bool in_bar = (x - 3) % 8 >= 0 && (x - 3) % 8 < 4 && x >= 3;
    for (int y : {0, 7}) EXPECT_EQ(frame3.pixel(x, y)[0], in_bar ? 1.0f : 0.0f) << "x " << x << " y " << y;
  }
  const ImageRGBA frame6 = drawn(TimingPattern::tearing, 6, 64, 8, *display);
  EXPECT_EQ(frame6.pixel(0, 0)[0], 1.0f) << "the bar entering at x = -2 covers x = 0..1";
  EXPECT_EQ(frame6.pixel(2, 0)[0], 0.0f);
  EXPECT_EQ(frame6.pixel(63, 0)[0], 1.0f);
}

TEST(TimingTestStatistics, NearestRankPercentilesAndIntervalFiguresAgainstHandWorkedValues) {
  std::vector<double> one_to_hundred;
  for (int i = 100; i >= 1; --i) one_to_hundred.push_back(i);
  const Percentiles p = percentiles(one_to_hundred);
  EXPECT_EQ(p.p50_s, 50.0);
  EXPECT_EQ(p.p99_s, 99.0);
  EXPECT_EQ(p.max_s, 100.0);
  EXPECT_EQ(percentiles({7.0}).p99_s, 7.0);
  // Flips at 0, 10, 20, 40, 50 ms (a missed refresh at 100 Hz): intervals 10, 10, 20, 10 ms, mean
  // 12.5 ms, sample SD sqrt((3 * 2.5^2 + 7.5^2) / 3) = 5 ms.
  const FlipTimingFigures figures = flip_timing_figures({0.0, 0.010, 0.020, 0.040, 0.050}, 100.0, 1, {}, {}, {});
  EXPECT_EQ(figures.frames, 5);
  EXPECT_NEAR(figures.interval_mean_s, 0.0125, 1e-15);
  EXPECT_NEAR(figures.interval_sd_s, 0.005, 1e-15);
  EXPECT_NEAR(figures.interval_max_s, 0.020, 1e-15);
  EXPECT_NEAR(figures.interval_min_s, 0.010, 1e-15);
  EXPECT_THAT(figures.describe(), ::testing::HasSubstr("mean 12.500000 ms (nominal 10.000000 ms, +2.500000 ms), SD "
                                                       "5.000000 ms, min 10.000000 ms, max 20.000000 ms; missed "
                                                       "deadlines 1"));
}

}  // namespace
}  // namespace glarelab
