// A `glarelab timing-test` session in the report (analysis/timing_figures.h): the flip-interval
// histogram and the time series read back from their SVG give the intervals the session was built
// with (57 of one refresh, 3 of two, at known flips), and a session without response times gets
// no empty response-time chart.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "analysis/analysis_report.h"
#include "tests/analysis_synthetic.h"
#include "tests/scratch_dir.h"
#include "tests/svg_read.h"

namespace glarelab::analysis {
namespace {

constexpr double kPeriod_s = 1.0 / 60.0;

// One timing_test trial of 61 flips at 60 Hz; the flips at 10, 30 and 31 come a refresh late
// (missed deadlines), so their intervals are two periods.
// Without `late_flips` every flip is on time, at k / 60 s as a virtual clock places it.
std::string timing_test_database(const test::ScratchDir& dir, bool late_flips = true) {
  const std::string db = dir.file("timing.db");
  ResultStore store(db);
  SessionRecord session = test::synthetic_session("rig");
  session.clock = "monotonic";
  const std::int64_t id = store.begin_session(session);
  TrialRecord trial;
  trial.session_id = id;
  trial.trial_index = 0;
  trial.procedure = "timing_test";
  trial.condition = R"({"name":"timing_test","pattern":"flicker","frames":"61"})";
  trial.onset_s = 0.0;
  trial.started_utc = "2026-01-01T00:00:00.000Z";
  std::vector<FrameRecord> frames;
  double flip_s = 0.0;
  for (int f = 0; f < 61; ++f) {
    const bool late = late_flips && (f == 10 || f == 30 || f == 31);
    if (f > 0) flip_s = late_flips ? flip_s + (late ? 2.0 : 1.0) * kPeriod_s : f / 60.0;
    FrameRecord frame;
    frame.frame_index = f;
    frame.scheduled_s = flip_s - (late ? kPeriod_s : 0.0);
    frame.flip_s = flip_s;
    frame.dropped = late;
    frames.push_back(frame);
  }
  store.commit_trial(trial, frames);
  store.finish_session(id, "completed");
  return db;
}

const std::string* figure_svg(const AnalysisReport& report, const std::string& stem) {
  for (const Figure& figure : report.figures)
    if (figure.file_stem == stem) return &figure.svg;
  return nullptr;
}

TEST(AnalysisTimingFigures, FlipIntervalHistogramAndSeriesGiveTheSessionsIntervals) {
  test::ScratchDir dir;
  const AnalysisReport report = analyse(load_databases({timing_test_database(dir)}), AnalysisOptions{});
  EXPECT_EQ(figure_svg(report, "response_times"), nullptr);  // no answered trials: no empty chart

  const std::string* histogram = figure_svg(report, "flip_intervals_1");
  ASSERT_NE(histogram, nullptr);
  // Two bars: 57 intervals of 16.667 ms, 3 of 33.333 ms (their heights in that ratio), at those values.
  std::vector<test::SvgBar> bars;
  for (const test::SvgBar& bar : test::svg_bars(*histogram))
    if (bar.height > 0.0) bars.push_back(bar);
  ASSERT_EQ(bars.size(), 2u);
  std::sort(bars.begin(), bars.end(), [](const auto& a, const auto& b) { return a.x < b.x; });
  EXPECT_NEAR(bars[0].height / bars[1].height, 57.0 / 3.0, 0.02);
  const auto ticks = test::svg_x_ticks(*histogram);
  ASSERT_GE(ticks.size(), 2u);
  const auto value_at = [&](double px) {
    return ticks.front().second + (px - ticks.front().first) * (ticks.back().second - ticks.front().second) /
                                      (ticks.back().first - ticks.front().first);
  };
  // A bin spans 1/40 of 16.667 ms from the shortest to the longest interval, which lie on the
  // outer edges of the first and last bin: each bar's centre half a bin from its interval (to the
  // pixel coordinates' 0.01 px).
  const double bin_ms = (2e3 * kPeriod_s - 1e3 * kPeriod_s) / 40.0;
  EXPECT_NEAR(value_at(bars[0].x + 0.5 * bars[0].width), 1e3 * kPeriod_s + 0.5 * bin_ms, 0.01 * bin_ms);
  EXPECT_NEAR(value_at(bars[1].x + 0.5 * bars[1].width), 2e3 * kPeriod_s - 0.5 * bin_ms, 0.01 * bin_ms);
  EXPECT_NE(histogram->find("60 intervals, 3 missed deadline(s)"), std::string::npos);
  // The mean interval (the measured period): 63 periods over 60 intervals.
  EXPECT_NE(histogram->find("mean 17.500 ms"), std::string::npos);

  const std::string* series = figure_svg(report, "flip_series_1");
  ASSERT_NE(series, nullptr);
  const auto series_ticks = test::svg_x_ticks(*series);
  ASSERT_GE(series_ticks.size(), 2u);
  const auto flip_at = [&](double px) {
    return series_ticks.front().second + (px - series_ticks.front().first) *
                                             (series_ticks.back().second - series_ticks.front().second) /
                                             (series_ticks.back().first - series_ticks.front().first);
  };
  std::vector<double> late_flips;
  for (const test::SvgCircle& c : test::svg_circles(*series))
    if (c.colour == "#d00") late_flips.push_back(flip_at(c.cx));
  ASSERT_EQ(late_flips.size(), 3u);
  // Interval i (1-based) is the one before flip i (0-based frames): flips 10, 30, 31.
  EXPECT_NEAR(late_flips[0], 10.0, 0.01);
  EXPECT_NEAR(late_flips[1], 30.0, 0.01);
  EXPECT_NEAR(late_flips[2], 31.0, 0.01);
  std::size_t longest = 0;
  for (const test::SvgLine& line : test::svg_polylines(*series)) longest = std::max(longest, line.points.size());
  EXPECT_EQ(longest, 60u);  // every interval drawn
}

// Intervals equal but for rounding (flips at k / 60 s): one bar, at the period, wider than a pixel.
TEST(AnalysisTimingFigures, EqualIntervalsGiveOneVisibleBar) {
  test::ScratchDir dir;
  const AnalysisReport report = analyse(load_databases({timing_test_database(dir, false)}), AnalysisOptions{});
  const std::string* histogram = figure_svg(report, "flip_intervals_1");
  ASSERT_NE(histogram, nullptr);
  std::vector<test::SvgBar> bars;
  for (const test::SvgBar& bar : test::svg_bars(*histogram))
    if (bar.height > 0.0) bars.push_back(bar);
  ASSERT_EQ(bars.size(), 1u);
  EXPECT_GT(bars[0].width, 1.0);
  const auto ticks = test::svg_x_ticks(*histogram);
  ASSERT_GE(ticks.size(), 2u);
  const double centre = ticks.front().second + (bars[0].x + 0.5 * bars[0].width - ticks.front().first) *
                                                   (ticks.back().second - ticks.front().second) /
                                                   (ticks.back().first - ticks.front().first);
  EXPECT_NEAR(centre, 1e3 * kPeriod_s, 2.0 / 40.0);  // within a bin of the 2 ms window
}

}  // namespace
}  // namespace glarelab::analysis
