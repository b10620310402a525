// The smaller findings of a lab's first study, each fixed: calibrate names a bad reading's place
// once; a bad value in a condition table is reported at its own cell; the adjustment example's
// spots start no brighter than its display can show; the Luidolt example's questions read.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cli_process.h"
#include "protocols/experiment.h"
#include "protocols/procedure.h"
#include "scratch_dir.h"
#include "stimuli/scene_library.h"

namespace glarelab {
namespace {

std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

TEST(FirstStudyFindings, CalibrateNamesTheBadReadingsPlaceOnce) {
  const test::ScratchDir dir;
  const auto run = test::run_glarelab({"calibrate", "--display", "offscreen", "--levels", "2", "--measurements",
                                       dir.write("nonmono.txt", "0.2 50\n0.2 180\n0.2 18\n0.2 0.1\n"), "--out",
                                       dir.file("display.csv")},
                                      dir.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_EQ(occurrences(run.output, "nonmono.txt:4:5"), 1u) << run.output;
  EXPECT_THAT(run.output, ::testing::HasSubstr("white level 2 of 2 (code 255 of 255) (reading 8 of 8): 0.1 cd/m2"));
}

TEST(FirstStudyFindings, ACsvValueErrorPointsAtTheBadCell) {
  const test::ScratchDir dir;
  const std::string bad_row = "ratio_1.15,lamp_100,lamp_115,contrl,control";
  test::write_bytes(dir.file("conditions.csv"), "name,scene_a,scene_b,glare_a,glare_b\nratio_1.05,lamp_100,lamp_105,"
                                                "control,control\n" + bad_row + "\n");
  const auto experiment = test::demo_variant(dir.path(), {{"file", "file = \"" + dir.file("conditions.csv") + "\""}});
  const auto run = test::run_glarelab({"validate", experiment.string()}, dir.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  // Line 3, the column where 'contrl' starts (1-based), not column 1.
  const std::string cell = dir.file("conditions.csv") + ":3:" + std::to_string(bad_row.find("contrl") + 1) + ": ";
  EXPECT_THAT(run.output, ::testing::HasSubstr(cell + "key 'condition 'ratio_1.15' glare_a': unknown glare mode 'contrl'"));
}

TEST(FirstStudyFindings, AdjustmentExampleSpotsStartWithinTheDisplaysPeak) {
  const Experiment experiment = load_experiment(std::string(GLARELAB_SOURCE_DIR) + "/examples/ritschel_adjustment.toml");
  const SceneLibrary scenes(experiment.scenes, experiment.display);
  const auto procedure = make_procedure(experiment, scenes.peak_luminances_cd_m2());
  const double peak_cd_m2 = experiment.display.peak_luminance_cd_m2;
  const double range_log10 = experiment.adjustment.start_range_log10;
  int capped = 0;
  while (!procedure->finished()) {
    const TrialPlan plan = procedure->next_trial();
    const double target_cd_m2 = plan.source_luminance_cd_m2.at(1);
    for (const double start : plan.adjustment_start_cd_m2) {
      EXPECT_LE(start, peak_cd_m2) << plan.condition_name;
      EXPECT_GE(std::log10(start / target_cd_m2), -range_log10 - 1e-12) << plan.condition_name;
      EXPECT_LE(std::log10(start / target_cd_m2), range_log10 + 1e-12) << plan.condition_name;
    }
    capped += target_cd_m2 * std::pow(10.0, range_log10) > peak_cd_m2 ? 1 : 0;
    procedure->record_response(plan, Response{"100 100", 1.0});  // both spots set: the next trial
  }
  EXPECT_GT(capped, 0) << "the example's bright target reaches above its display's peak within the range";
}

TEST(FirstStudyFindings, LuidoltExampleAsksForTheOverallSimilarity) {
  const Experiment experiment = load_experiment(std::string(GLARELAB_SOURCE_DIR) + "/examples/luidolt_ratings.toml");
  const SceneLibrary scenes(experiment.scenes, experiment.display);
  const auto procedure = make_procedure(experiment, scenes.peak_luminances_cd_m2());
  int overall = 0;
  while (!procedure->finished()) {
    const TrialPlan plan = procedure->next_trial();
    EXPECT_EQ(plan.question.find("Rate the overall from"), std::string::npos) << plan.question;
    if (plan.condition_json.find("\"category\":\"overall\"") != std::string::npos) {
      ++overall;
      EXPECT_EQ(plan.question, "Rate the overall similarity from 1 (completely different) to 7 (exactly the same)");
    }
    procedure->record_response(plan, Response{"4", 1.0});
  }
  EXPECT_GT(overall, 0);
  // A label for a category that is not one is refused at its key.
  const std::string text = "[experiment]\nname = \"r\"\n[scenes]\na = { file = \"a.exr\" }\n[procedure]\ntype = "
                           "\"rating\"\ncategories = [\"overall\"]\ncategory_labels = { overal = \"x\" }\n"
                           "[[conditions.rows]]\nname = \"c\"\nscene = \"a\"\n";
  try {
    parse_experiment_text(text, "r.toml", "/");
    FAIL() << "an unknown category's label was accepted";
  } catch (const ConfigError& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("r.toml:8:"));
    EXPECT_THAT(error.what(), ::testing::HasSubstr("procedure.category_labels.overal"));
  }
}

}  // namespace
}  // namespace glarelab
