// The report draws psignifit 4's fit for every psychometric function (issue: `analyze` uses the
// psignifit-standard fit for every curve it draws): the pooled graded-choice figure and the
// staircase figures. Each drawn threshold equals what `glarelab fit` (a separate process reading
// a CSV table and psignifit's options JSON) gives for the same pooled table; the drawn curve
// passes through the drawn threshold; the rings sized by trials never overlap and every interval
// stays inside the plotting area.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "analysis/analysis_report.h"
#include "analysis/graded_choice_report.h"
#include "analysis/report_numbers.h"
#include "analysis/svg_plot.h"
#include "core/random.h"
#include "tests/analysis_synthetic.h"
#include "tests/cli_process.h"
#include "tests/example_dry_run.h"
#include "tests/scratch_dir.h"
#include "tests/svg_read.h"

namespace glarelab::analysis {
namespace {

using nlohmann::json;

// `glarelab fit` on the levels as a DATA.csv with the given OPTIONS.json: its RESULT.json.
json fit_command(const test::ScratchDir& dir, const std::string& stem, const std::vector<StimulusLevel>& levels,
                 const std::string& options_json) {
  std::ostringstream table;
  table << "level,correct,trials\n";
  table.precision(17);
  for (const StimulusLevel& level : levels) table << level.intensity << ',' << level.correct << ',' << level.trials << '\n';
  const std::string data = dir.write(stem + ".csv", table.str());
  const std::string options = dir.write(stem + ".json", options_json);
  const std::string out = dir.file(stem + "_result.json");
  const test::RunOutput run = test::run_glarelab({"fit", data, "--options", options, "--out", out}, dir.path());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  std::ifstream in(out);
  return json::parse(in);
}

const Figure& figure_named(const AnalysisReport& report, const std::string& stem) {
  for (const Figure& figure : report.figures)
    if (figure.file_stem == stem) return figure;
  throw std::runtime_error("no figure " + stem);
}

// No two rings (hollow markers: the data) overlap: centres at least the sum of the radii apart.
void expect_rings_apart(const std::string& svg) {
  std::vector<test::SvgCircle> rings;
  for (const test::SvgCircle& c : test::svg_circles(svg))
    if (c.hollow) rings.push_back(c);
  ASSERT_FALSE(rings.empty());
  for (std::size_t i = 0; i < rings.size(); ++i)
    for (std::size_t j = i + 1; j < rings.size(); ++j)
      EXPECT_GE(std::hypot(rings[i].cx - rings[j].cx, rings[i].cy - rings[j].cy), rings[i].r + rings[j].r - 0.02)
          << "rings at " << rings[i].cx << "," << rings[i].cy << " and " << rings[j].cx << "," << rings[j].cy;
}

// Every point of every interval path (bars, caps and arrowheads) inside the plotting area.
void expect_intervals_inside(const std::string& svg) {
  const test::SvgBox area = test::svg_plot_area(svg);
  for (const auto& [colour, points] : test::svg_paths(svg))
    for (const auto& [x, y] : points) EXPECT_TRUE(area.holds(x, y)) << colour << " interval point " << x << "," << y;
}

// The curve of `colour` through the filled dot of that colour (the threshold): within 1.5 px.
void expect_curve_through_dot(const std::string& svg, const std::string& colour, double radius) {
  const test::SvgCircle* dot = nullptr;
  const auto circles = test::svg_circles(svg);
  for (const test::SvgCircle& c : circles)
    if (!c.hollow && c.colour == colour && std::abs(c.r - radius) < 0.01) dot = &c;
  ASSERT_NE(dot, nullptr) << colour;
  bool found = false;
  for (const test::SvgLine& line : test::svg_polylines(svg)) {
    if (line.colour != colour) continue;
    found = true;
    EXPECT_NEAR(test::polyline_y_at(line, dot->cx), dot->cy, 1.5) << colour;
  }
  EXPECT_TRUE(found) << colour;
}

// examples/demo.toml answered by two simulated participants: each glare group's drawn PSE is the
// MAP threshold `glarelab fit` finds for the group's pooled table (yes/no, cumulative normal,
// guess and lapse fixed at 0: the options the figure's fit uses), and so are its interval ends.
TEST(AnalysisDrawnFits, GradedChoiceCurvesAreTheFitCommandsFitOfThePooledTable) {
  test::ScratchDir dir;
  const std::string db = dir.file("demo.db");
  test::dry_run_example(std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml", db, {1, 2});
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  options.threads = 2;
  const AnalysisReport report = analyse(load_databases({db}), options);
  ASSERT_GE(report.graded_choice.groups.size(), 2u);
  const std::string& svg = figure_named(report, "graded_choice").svg;
  for (std::size_t g = 0; g < report.graded_choice.groups.size(); ++g) {
    const GradedChoiceGroup& group = report.graded_choice.groups[g];
    ASSERT_TRUE(group.psignifit) << group.name;
    const json result = fit_command(dir, "group" + std::to_string(g), group.levels,
                                    R"({"expType": "YesNo", "sigmoidName": "norm", "fixedPars": [null, null, 0, 0, null]})");
    const double threshold = result["MAP"][0].get<double>();
    EXPECT_NEAR(group.psignifit->pse, threshold, 1e-9) << group.name;
    EXPECT_NEAR(group.psignifit->credible.low, result["conf_Intervals"][0][0][0].get<double>(), 1e-9) << group.name;
    EXPECT_NEAR(group.psignifit->credible.high, result["conf_Intervals"][0][1][0].get<double>(), 1e-9) << group.name;
    // The legend prints the same number, and the drawn curve passes through the drawn PSE at 1/2.
    EXPECT_NE(svg.find(group.name + ": PSE " + graded_value_text(report.graded_choice, threshold)), std::string::npos)
        << group.name;
    expect_curve_through_dot(svg, series_colour(g), 4.5);
  }
  expect_rings_apart(svg);
  expect_intervals_inside(svg);
}

// A 2-AFC staircase (synthetic: levels 1 to 8, P(correct) = 0.5 + 0.5 Phi((x - 4.5) / 1.5) drawn
// from the counter-based generator): the psychometric figure draws the MAP of `glarelab fit` with
// expType 2AFC on the track's table.
TEST(AnalysisDrawnFits, StaircaseCurveIsTheFitCommandsFitOfTheTrack) {
  test::ScratchDir dir;
  const std::string db = dir.file("staircase.db");
  {
    ResultStore store(db);
    const std::int64_t id = store.begin_session(test::synthetic_session("P1"));
    const CounterRandom random(7, RandomStream::observer);
    std::vector<test::TrialSpec> specs;
    for (int i = 0; i < 80; ++i) {
      test::TrialSpec spec;
      spec.procedure = "staircase";
      spec.condition = R"({"name":"track","alternatives":2})";
      spec.staircase = "track";
      spec.intensity = 1.0 + static_cast<double>(i % 8);
      const double p = 0.5 + 0.5 * 0.5 * std::erfc(-(*spec.intensity - 4.5) / 1.5 / std::sqrt(2.0));
      spec.correct = random.uniform(static_cast<std::uint64_t>(i)) < p ? 1 : 0;
      spec.response = *spec.correct ? "right" : "left";
      spec.reversal = 0;
      specs.push_back(spec);
    }
    test::commit_trials(store, id, specs);
    store.finish_session(id, "completed");
  }
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  options.threads = 2;
  const AnalysisReport report = analyse(load_databases({db}), options);
  ASSERT_EQ(report.staircases.size(), 1u);
  const StaircaseResult& track = report.staircases.front();
  ASSERT_TRUE(track.psignifit) << track.psignifit_note;
  std::vector<std::pair<double, bool>> trials;
  for (const StaircasePoint& p : track.track) trials.emplace_back(p.intensity, p.correct);
  const json result = fit_command(dir, "track", levels_from_trials(trials), R"({"expType": "2AFC", "sigmoidName": "norm"})");
  EXPECT_NEAR(track.psignifit->map[0], result["MAP"][0].get<double>(), 1e-9);
  EXPECT_NEAR(track.psignifit->intervals[0][0].low, result["conf_Intervals"][0][0][0].get<double>(), 1e-9);
  EXPECT_NEAR(track.psignifit->intervals[0][0].high, result["conf_Intervals"][0][1][0].get<double>(), 1e-9);
  const std::string& svg = figure_named(report, "psychometric_1").svg;
  EXPECT_NE(svg.find("threshold " + general(result["MAP"][0].get<double>())), std::string::npos);
  EXPECT_EQ(svg.find("Weibull"), std::string::npos);  // no maximum-likelihood curves drawn beside it
  expect_curve_through_dot(svg, series_colour(0), 4.5);
  expect_rings_apart(svg);
  expect_intervals_inside(svg);
}

// An interval beyond the axis range stops at the plot's edge with an arrowhead, not a cap.
TEST(AnalysisDrawnFits, IntervalsBeyondTheRangeStopAtTheEdgeWithAnArrowhead) {
  SvgPlot plot("t", "x", "y");
  plot.set_x_range(0.0, 1.0);
  plot.set_y_range(0.0, 1.0);
  plot.horizontal_error_bar(0.5, -3.0, 0.6, "#111111");
  plot.error_bar(0.5, 0.2, 7.0, "#222222");
  const std::string svg = plot.svg();
  expect_intervals_inside(svg);
  const auto paths = test::svg_paths(svg);
  ASSERT_EQ(paths.size(), 2u);
  // M x0,y H x1, then the low end as an arrowhead (M, L, L: three points), the high end a cap (M, V).
  EXPECT_EQ(paths[0].second.size(), 2u + 3u + 2u);
  EXPECT_EQ(paths[1].second.size(), 2u + 2u + 3u);
  const test::SvgBox area = test::svg_plot_area(svg);
  EXPECT_NEAR(paths[0].second[0].first, area.x, 0.01);      // the horizontal bar starts at the left edge
  EXPECT_NEAR(paths[1].second[1].second, area.y, 0.01);     // the vertical bar ends at the top edge
}

}  // namespace
}  // namespace glarelab::analysis
