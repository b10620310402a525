// examples/glare_quest_plus.toml answered by its simulated observer and analysed as `analyze`
// does (the posteriors rebuilt by the runner), read back from the report as a reader sees it: the
// threshold figure's axis is in the QUEST+ parameter's own unit (its label, and its range the
// grid's ends in the experiment file), the plotted values are the track's grid in that unit, no
// staircase analysis of a QUEST+ track appears, and an estimate at a grid edge is flagged.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "analysis/analysis_report.h"
#include "analysis/report_output.h"
#include "runner/cli/quest_plus_posteriors.h"
#include "tests/example_dry_run.h"
#include "tests/scratch_dir.h"
#include "tests/svg_read.h"

namespace glarelab::analysis {
namespace {

// The example, with `from` replaced by `to` (nothing replaced when empty), beside its scenes.
std::string quest_plus_example(const test::ScratchDir& dir, const std::string& from = {}, const std::string& to = {}) {
  const std::filesystem::path examples = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples";
  std::ifstream in(examples / "glare_quest_plus.toml");
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  if (!from.empty()) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  if (!std::filesystem::exists(dir.path() / "scenes")) std::filesystem::create_directory_symlink(examples / "scenes", dir.path() / "scenes");
  return dir.write("glare_quest_plus.toml", text);
}

AnalysisReport analysed(const std::string& db) {
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  options.threads = 2;
  AnalysisReport report = analyse(load_databases({db}), options);
  add_quest_plus_posteriors(report, rebuild_quest_plus_posteriors(report.data, report.data.notes));
  return report;
}

// Pixel x to value, from the figure's first and last x tick labels.
double value_at(const std::vector<std::pair<double, double>>& ticks, double px) {
  const auto& [p0, v0] = ticks.front();
  const auto& [p1, v1] = ticks.back();
  return v0 + (px - p0) * (v1 - v0) / (p1 - p0);
}

// The example's threshold grid: 40.2 to 46.0 dB cd/m2 in steps of 0.2 (`threshold = { from = 40.2,
// to = 46.0, step = 0.2 }`, intensity_unit = "db_cd_m2"), 30 values.
constexpr double kLowest_db = 40.2, kHighest_db = 46.0, kStep_db = 0.2;

TEST(AnalysisQuestPlusReport, ThresholdFigureIsInTheParametersOwnUnitAndNoStaircaseAnalysisAppears) {
  test::ScratchDir dir;
  const std::string db = dir.file("quest_plus.db");
  test::dry_run_example(quest_plus_example(dir), db, {1});
  const AnalysisReport report = analysed(db);
  EXPECT_TRUE(report.staircases.empty());
  ASSERT_EQ(report.quest_plus.size(), 2u);
  int figures_read = 0;
  for (const Figure& figure : report.figures) {
    EXPECT_NE(figure.section, "staircase") << figure.file_stem;
    EXPECT_EQ(figure.file_stem.find("psychometric"), std::string::npos) << figure.file_stem;
    if (figure.section != "quest_plus" || figure.svg.find(">threshold (dB cd/m2)<") == std::string::npos) continue;
    ++figures_read;
    const auto ticks = test::svg_x_ticks(figure.svg);
    ASSERT_GE(ticks.size(), 2u) << figure.file_stem;
    const test::SvgBox area = test::svg_plot_area(figure.svg);
    // The axis runs over the grid in dB: its ends are the grid's first and last value.
    EXPECT_NEAR(value_at(ticks, area.x), kLowest_db, 0.01) << figure.file_stem;
    EXPECT_NEAR(value_at(ticks, area.x + area.width), kHighest_db, 0.01) << figure.file_stem;
    // The plotted points are the grid's values in dB (not cd/m2: 10^(40.2/20) = 102.3).
    std::vector<double> plotted;
    for (const test::SvgCircle& c : test::svg_circles(figure.svg))
      if (!c.hollow && std::abs(c.r - 3.5) < 0.01) plotted.push_back(value_at(ticks, c.cx));
    ASSERT_EQ(plotted.size(), 30u) << figure.file_stem;
    for (std::size_t i = 0; i < plotted.size(); ++i)
      EXPECT_NEAR(plotted[i], kLowest_db + kStep_db * static_cast<double>(i), 0.01) << figure.file_stem << " point " << i;
  }
  EXPECT_EQ(figures_read, 2);  // one threshold figure per track
  const std::string html = render_html(report);
  const std::string terminal = render_terminal_summary(report);
  for (const std::string* text : {&html, &terminal}) {
    EXPECT_EQ(text->find("never reversed"), std::string::npos);
    EXPECT_EQ(text->find("QUEST estimate"), std::string::npos);
    EXPECT_EQ(text->find("Staircases and QUEST"), std::string::npos);
  }
}

// An observer whose threshold lies 10 dB above the reference (50 dB, above the grid's 46.0 and the
// brightest comparison, 47.8 dB): the answers stay near chance, the threshold's posterior piles up
// at the grid's highest value, and the table, the terminal and the figure say so.
TEST(AnalysisQuestPlusReport, AnEstimateAtTheGridsEdgeIsFlagged) {
  test::ScratchDir dir;
  const std::string db = dir.file("quest_plus_edge.db");
  test::dry_run_example(quest_plus_example(dir, "threshold_log10 = 0.05", "threshold_log10 = 0.5"), db, {1});
  const AnalysisReport report = analysed(db);
  ASSERT_FALSE(report.quest_plus.empty());
  const QuestPlusPosterior& track = report.quest_plus.front();
  ASSERT_EQ(track.track, "threshold_slope_lapse");
  const MarginalPosterior& threshold = track.marginals.front();
  ASSERT_EQ(threshold.parameter, "threshold");
  EXPECT_NEAR(threshold.mode, kHighest_db, 0.5 * kStep_db);  // the edge the test is about is reached
  const std::string* svg = nullptr;
  for (const Figure& figure : report.figures)
    if (figure.file_stem == "quest_plus_1_1") svg = &figure.svg;
  ASSERT_NE(svg, nullptr);
  EXPECT_NE(svg->find("warning: the threshold mode (46 dB cd/m2) sits at the grid"), std::string::npos) << *svg;
  EXPECT_NE(render_html(report).find("sits at the grid&#39;s highest value"), std::string::npos);
  EXPECT_NE(render_terminal_summary(report).find("sits at the grid's highest value (46 dB cd/m2)"), std::string::npos);
}

}  // namespace
}  // namespace glarelab::analysis
