// The [analysis] table of an experiment file (protocols/analysis_config.h): its words reach the
// report's figures through the stored session (runner/cli/analysis_words.h), the figures have
// their own words without it, and a misspelt or empty key is refused at file:line:column.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "analysis/analysis_report.h"
#include "analysis/quest_plus_posterior.h"
#include "runner/cli/analysis_words.h"
#include "tests/example_dry_run.h"
#include "tests/experiment_error.h"
#include "tests/scratch_dir.h"
#include "tests/svg_read.h"

namespace glarelab::analysis {
namespace {

// examples/demo.toml without its own [analysis] table (the file's last), copied beside its
// condition table (the scenes linked), with `extra` appended.
std::string demo_with(const test::ScratchDir& dir, const std::string& extra) {
  const std::filesystem::path examples = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples";
  std::ifstream in(examples / "demo.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::filesystem::copy_file(examples / "demo_conditions.csv", dir.path() / "demo_conditions.csv",
                             std::filesystem::copy_options::overwrite_existing);
  if (!std::filesystem::exists(dir.path() / "scenes")) std::filesystem::create_directory_symlink(examples / "scenes", dir.path() / "scenes");
  std::string own = text.str();
  const std::size_t analysis = own.find("\n[analysis]");
  EXPECT_NE(analysis, std::string::npos) << "examples/demo.toml has no [analysis] table";
  own = own.substr(0, analysis);
  return dir.write("demo.toml", own + "\n" + extra);
}

std::string graded_svg(const std::string& db) {
  LoadedData data = load_databases({db});
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  options.threads = 2;
  options.words = cli::figure_words_of(data);
  const AnalysisReport report = analyse(std::move(data), options);
  for (const Figure& figure : report.figures)
    if (figure.file_stem == "graded_choice") return figure.svg;
  return {};
}

// The demo with an [analysis] table: the axis words, the unit and the groups' display names are
// the figure's, and the column names are not.
TEST(AnalysisFigureWords, TheTablesWordsReachTheGradedFigure) {
  test::ScratchDir dir;
  const std::string experiment = demo_with(dir, R"([analysis]
graded_label = "comparison luminance relative to the reference"
graded_unit = "ratio"
answer_label = "proportion judging the comparison brighter"
group_label = "glare on the reference"

[analysis.names]
control = "no glare"
static = "frozen eye"
dynamic = "moving eye"
)");
  const std::string db = dir.file("demo.db");
  test::dry_run_example(experiment, db, {1});
  const std::string svg = graded_svg(db);
  ASSERT_FALSE(svg.empty());
  EXPECT_NE(svg.find(">comparison luminance relative to the reference (ratio), log10 scale<"), std::string::npos) << svg;
  EXPECT_NE(svg.find("proportion judging the comparison brighter"), std::string::npos);
  EXPECT_NE(svg.find("glare on the reference"), std::string::npos);
  for (const char* name : {">no glare: PSE ", ">frozen eye: PSE ", ">moving eye: PSE "})
    EXPECT_NE(svg.find(name), std::string::npos) << name;
  EXPECT_EQ(svg.find("scene_b"), std::string::npos);
  EXPECT_EQ(svg.find("luminance_ratio"), std::string::npos);
}

// Without the table the figure builds its words from the data: the column's name as words, the
// scale said, the answer counted.
TEST(AnalysisFigureWords, WithoutTheTableTheFigureHasItsOwnWords) {
  test::ScratchDir dir;
  const std::string db = dir.file("demo.db");
  test::dry_run_example(demo_with(dir, ""), db, {1});
  const std::string svg = graded_svg(db);
  EXPECT_NE(svg.find(">luminance ratio, log10 scale<"), std::string::npos) << svg;
  EXPECT_NE(svg.find("proportion choosing scene_b"), std::string::npos);
  EXPECT_NE(svg.find(">control: PSE "), std::string::npos);
}

// The line of `needle` in `text`, 1-based.
int line_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

TEST(AnalysisFigureWords, UnknownAndEmptyKeysAreRefusedAtTheirPlace) {
  test::ScratchDir dir;
  const std::string misspelt = demo_with(dir, "[analysis]\ngraded_lable = \"x\"\n");
  std::ifstream in(misspelt);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string error = test::experiment_error(misspelt);
  EXPECT_NE(error.find("demo.toml:" + std::to_string(line_of(text, "graded_lable")) + ":1"), std::string::npos) << error;
  EXPECT_NE(error.find("analysis.graded_lable"), std::string::npos) << error;
  EXPECT_NE(error.find("graded_label"), std::string::npos) << error;  // the suggestion

  const std::string empty = test::experiment_error(demo_with(dir, "[analysis]\nanswer_label = \"\"\n"));
  EXPECT_NE(empty.find("analysis.answer_label"), std::string::npos) << empty;
  EXPECT_NE(empty.find("must not be empty"), std::string::npos) << empty;

  const std::string number = test::experiment_error(demo_with(dir, "[analysis.names]\ncontrol = 3\n"));
  EXPECT_NE(number.find("analysis.names.control"), std::string::npos) << number;
  EXPECT_NE(number.find("expected a string"), std::string::npos) << number;
}

// The display names reach the Spencer PSE figure's legend and the QUEST+ posterior's title; a name
// the table does not give stays as stored, and the QUEST+ method is named as its paper names it.
TEST(AnalysisFigureWords, DisplayNamesReachThePseLegendAndTheQuestPlusTitle) {
  AnalysisReport report;
  report.options.words.names = {{"with_context", "with context"}, {"threshold_slope_lapse", "three-parameter track"}};
  report.pse.tracks.push_back(PseTrack{});
  for (const std::string group : {"with_context", "without_context"})
    for (const double gain : {0.0, 1.0}) report.pse.points.push_back({group, gain, 0.8, std::nullopt, 1});
  const std::vector<Figure> figures = draw_figures(report);
  const auto pse = std::find_if(figures.begin(), figures.end(), [](const Figure& f) { return f.file_stem == "pse"; });
  ASSERT_NE(pse, figures.end());
  EXPECT_NE(pse->svg.find("with context"), std::string::npos) << pse->svg;
  EXPECT_EQ(pse->svg.find("with_context"), std::string::npos);
  EXPECT_NE(pse->svg.find("without_context"), std::string::npos);

  QuestPlusPosterior track;
  track.participant_label = "P1";
  track.track = "threshold_slope_lapse";
  track.method = "quest_plus";
  track.trials = 3;
  track.marginals.push_back({"threshold", "dB cd/m2", {40.0, 41.0, 42.0}, {0.2, 0.5, 0.3}, 41.0, 41.1, 0.7});
  const std::string svg = marginal_posterior_svg(track, 0, report.options.words);
  EXPECT_NE(svg.find("QUEST+ posterior of threshold: three-parameter track, P1"), std::string::npos) << svg;
  EXPECT_EQ(svg.find("quest_plus"), std::string::npos);
}

// The forced-choice figure's legend and bar labels take the display names of options and of the
// group's values, as the graded-choice figure does.
TEST(AnalysisFigureWords, DisplayNamesReachTheForcedChoiceFigure) {
  AnalysisReport report;
  report.options.words.names = {{"dynamic", "moving eye"}, {"control", "no glare"}, {"lamp_130", "Lamp-130"}};
  PairPreference pair;
  pair.group = "scene=lamp_130";
  pair.option_a = "dynamic";
  pair.option_b = "control";
  pair.chose_a = 7;
  pair.chose_b = 3;
  report.forced_choice.groups.push_back(pair);
  report.forced_choice.trials = 10;
  const std::vector<Figure> figures = draw_figures(report);
  const auto forced = std::find_if(figures.begin(), figures.end(), [](const Figure& f) { return f.file_stem == "forced_choice"; });
  ASSERT_NE(forced, figures.end());
  for (const char* words : {"moving eye", "no glare", "Lamp-130"})
    EXPECT_NE(forced->svg.find(words), std::string::npos) << words << "\n" << forced->svg;
  EXPECT_EQ(forced->svg.find(">dynamic"), std::string::npos) << forced->svg;
}

}  // namespace
}  // namespace glarelab::analysis
