// The examples answered by their simulated observers (tests/example_dry_run.h, no rendering) and
// analysed: every PSE of the Spencer study has an estimate and a proper interval, QUEST+ tracks
// stay out of the staircase analysis and carry their own interval, and a scored 2-AFC shows its
// percent correct.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "analysis/analysis_report.h"
#include "analysis/report_output.h"
#include "runner/cli/quest_plus_posteriors.h"
#include "tests/example_dry_run.h"
#include "tests/scratch_dir.h"

namespace glarelab::analysis {
namespace {

std::string example(const std::string& name) { return std::string(GLARELAB_SOURCE_DIR) + "/examples/" + name; }

AnalysisReport analysed(const std::string& db) {
  AnalysisOptions options;
  options.bootstrap_samples = 20;
  options.threads = 2;
  return analyse(load_databases({db}), options);
}

// examples/spencer_staircase.toml: 24 tracks of 8 trials, whose answers often separate perfectly.
// Every one of the 24 PSEs is fitted (none from the reversal mean) with an interval of positive
// width around it.
TEST(AnalysisExamplesAcceptance, SpencerEveryPseHasAnEstimateAndAnInterval) {
  test::ScratchDir dir;
  const std::string db = dir.file("spencer.db");
  test::dry_run_example(example("spencer_staircase.toml"), db, {1});
  const AnalysisReport report = analysed(db);
  ASSERT_EQ(report.pse.tracks.size(), 24u);
  int separated = 0;
  for (const PseTrack& track : report.pse.tracks) {
    ASSERT_TRUE(track.pse_fraction) << track.name << ": " << track.note;
    EXPECT_FALSE(track.pse_from_reversals) << track.name;
    ASSERT_TRUE(track.pse_interval) << track.name;
    EXPECT_GT(track.pse_interval->high - track.pse_interval->low, 1e-3) << track.name;
    EXPECT_LE(track.pse_interval->low, *track.pse_fraction) << track.name;
    EXPECT_GE(track.pse_interval->high, *track.pse_fraction) << track.name;
    ASSERT_TRUE(track.fit) << track.name;
    // Perfect separation: every 'comparison brighter' above every 'reference brighter'.
    double highest_no = -1.0, lowest_yes = 2.0;
    for (const PsignifitBlock& block : track.fit->result.blocks) {
      if (block.correct > 0) lowest_yes = std::min(lowest_yes, block.level);
      if (block.correct < block.trials) highest_no = std::max(highest_no, block.level);
    }
    separated += highest_no < lowest_yes ? 1 : 0;
  }
  std::printf("Spencer: 24 PSEs with intervals; %d of 24 tracks separate perfectly\n", separated);
}

// examples/glare_quest_plus.toml: its tracks are QUEST+ (stored procedure "quest", method
// quest_plus); the staircase analysis takes none of them, the posterior section every one.
TEST(AnalysisExamplesAcceptance, QuestPlusTracksOnlyInTheirOwnSection) {
  test::ScratchDir dir;
  const std::string db = dir.file("quest_plus.db");
  test::dry_run_example(example("glare_quest_plus.toml"), db, {1});
  AnalysisReport report = analysed(db);
  EXPECT_TRUE(report.staircases.empty()) << report.staircases.front().name;
  add_quest_plus_posteriors(report, rebuild_quest_plus_posteriors(report.data, report.data.notes));
  ASSERT_FALSE(report.quest_plus.empty());
  for (const Figure& figure : report.figures) EXPECT_NE(figure.section, "staircase") << figure.file_stem;
  const std::string terminal = render_terminal_summary(report);
  EXPECT_EQ(terminal.find("never reversed"), std::string::npos) << terminal;
  EXPECT_NE(terminal.find(", 95% "), std::string::npos) << terminal;
}

// examples/demo.toml is a scored 2-AFC with a graded variable: the report gives percent correct
// with its interval.
TEST(AnalysisExamplesAcceptance, ScoredTwoAfcShowsPercentCorrect) {
  test::ScratchDir dir;
  const std::string db = dir.file("demo.db");
  test::dry_run_example(example("demo.toml"), db, {1});
  const AnalysisReport report = analysed(db);
  ASSERT_FALSE(report.forced_choice.scored.empty());
  const ScoredShare& total = report.forced_choice.scored.back();
  EXPECT_GT(total.trials, 0);
  EXPECT_LE(total.interval.low, total.percent() / 100.0);
  EXPECT_GE(total.interval.high, total.percent() / 100.0);
  EXPECT_NE(render_terminal_summary(report).find("percent correct"), std::string::npos);
}

}  // namespace
}  // namespace glarelab::analysis
