#include <gtest/gtest.h>

#include "protocols/experiment.h"
#include "experiment_error.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

// Lines 1-12 are fixed so tests can name exact locations; `procedure_extra` goes on line 12 and
// the [conditions] table starts at line 14.
std::string experiment_text(const std::string& procedure_extra, const std::string& conditions) {
  return "[experiment]\n"                                             // 1
         "name = \"glare pilot\"\n"                                   // 2
         "seed = 7\n"                                                 // 3
         "\n"                                                         // 4
         "[scenes]\n"                                                 // 5
         "dim = { file = \"scenes/dim.exr\" }\n"                      // 6
         "bright = { file = \"/abs/bright.exr\", scale_cd_m2 = 2.5 }\n"  // 7
         "\n"                                                         // 8
         "[procedure]\n"                                              // 9
         "type = \"forced_choice\"\n"                                 // 10
         "repetitions = 2\n"                                          // 11
         + procedure_extra + "\n"                                     // 12
         "\n"                                                         // 13
         "[conditions]\n"                                             // 14
         + conditions;                                                // 15...
}

const std::string kCsv =
    "name,scene_a,scene_b\n"
    "pair one,dim,bright\n"
    "pair two,bright,dim\n";

std::string error_of(const std::string& path) { return test::experiment_error(path); }

TEST(ExperimentFile, LoadsFileWithCsvConditionsAndDefaults) {
  test::ScratchDir dir;
  dir.write("conditions.csv", kCsv);
  const std::string path = dir.write("exp.toml", experiment_text("", "file = \"conditions.csv\"\n"));
  const Experiment e = load_experiment(path);
  EXPECT_EQ(e.source_file, path);
  EXPECT_EQ(e.name, "glare pilot");
  EXPECT_EQ(e.description, "");
  EXPECT_EQ(e.seed, 7u);
  EXPECT_EQ(e.display.width_px, DisplaySpec{}.width_px);
  EXPECT_EQ(e.display.encoding, DisplayEncoding::srgb);
  ASSERT_EQ(e.scenes.size(), 2u);
  EXPECT_EQ(e.scenes.at("dim").file, (dir.path() / "scenes/dim.exr").string());
  EXPECT_EQ(e.scenes.at("dim").scale_cd_m2, 1.0);
  EXPECT_EQ(e.scenes.at("bright").file, "/abs/bright.exr");
  EXPECT_EQ(e.scenes.at("bright").scale_cd_m2, 2.5);
  EXPECT_EQ(e.procedure, "forced_choice");
  EXPECT_EQ(e.forced_choice.repetitions, 2);
  EXPECT_EQ(e.forced_choice.responses, (std::vector<std::string>{"left", "right"}));
  ASSERT_EQ(e.conditions.size(), 2u);
  EXPECT_EQ(e.conditions[1].name(), "pair two");
  EXPECT_EQ(e.conditions[1].number, 2);
  EXPECT_EQ(e.conditions[1].where.to_string(), (dir.path() / "conditions.csv").string() + ":3:1");
  ASSERT_EQ(e.conditions[0].fields.size(), 3u);
  EXPECT_EQ(e.conditions[0].fields[2].first, "scene_b");
  EXPECT_EQ(*e.conditions[0].find("scene_a"), "dim");
  EXPECT_EQ(e.simulated_observer.slope, SimulatedObserverSpec{}.slope);
}

TEST(ExperimentFile, InlineRowsKeepColumnOrderAndEveryKeyIsRead) {
  const std::string text =
      "[experiment]\nname = \"x\"\ndescription = \"d\"\nseed = 0\n"
      "[display]\nwidth_px = 1920\nheight_px = 1080\nrefresh_hz = 120\nviewing_distance_mm = 700.5\n"
      "pixel_pitch_mm = 0.3\npeak_luminance_cd_m2 = 400\nbackground_cd_m2 = 1.5\nencoding = \"gamma\"\n"
      "gamma = 2.4\nmonitor = 1\nfullscreen = true\n"
      "[scenes]\na = { file = \"a.exr\" }\nb = { file = \"b.exr\" }\n"
      "[procedure]\ntype = \"forced_choice\"\nalternatives = 2\nlayout = \"side_by_side\"\n"
      "question = \"Which one glares more?\"\nstimulus_frames = 12\nrepetitions = 3\n"
      "counterbalance_sides = false\nresponses = [\"f\", \"j\"]\n"
      "[conditions]\nrows = [ { scene_b = \"b\", scene_a = \"a\", contrast = 0.25 }, "
      "{ scene_a = \"b\", scene_b = \"a\", flag = true, n = 3 } ]\n"
      "[observer.simulated]\nthreshold_log10 = 0.1\nslope = 2\nlapse = 0.04\nresponse_time_median_s = 0.8\n";
  const Experiment e = parse_experiment_text(text, "mem.toml", "/data/exp");
  EXPECT_EQ(e.display.refresh_hz, 120.0);
  EXPECT_EQ(e.display.encoding, DisplayEncoding::gamma);
  EXPECT_TRUE(e.display.fullscreen);
  EXPECT_EQ(e.scenes.at("a").file, "/data/exp/a.exr");
  EXPECT_EQ(e.forced_choice.responses, (std::vector<std::string>{"f", "j"}));
  EXPECT_FALSE(e.forced_choice.counterbalance_sides);
  EXPECT_EQ(e.simulated_observer.slope, 2.0);
  ASSERT_EQ(e.conditions.size(), 2u);
  const auto& fields = e.conditions[0].fields;
  ASSERT_EQ(fields.size(), 3u);
  EXPECT_EQ(fields[0], (std::pair<std::string, std::string>{"scene_b", "b"}));
  EXPECT_EQ(fields[1].first, "scene_a");
  EXPECT_EQ(fields[2], (std::pair<std::string, std::string>{"contrast", "0.25"}));
  EXPECT_EQ(*e.conditions[1].find("flag"), "true");
  EXPECT_EQ(*e.conditions[1].find("n"), "3");
  EXPECT_EQ(e.conditions[1].name(), "row 2");
  EXPECT_EQ(e.conditions[0].where.to_string(), "mem.toml:30:10");
}

TEST(ExperimentFile, ResolvedConfigReadsBackEqual) {
  test::ScratchDir dir;
  dir.write("conditions.csv",
            "scene_b,name,scene_a,note\n"
            "bright,\"quote \"\" and, comma\",dim,\"multi\nline\"\n"
            "dim,'single' \\ back,bright,tab\there\n");
  const std::string path = dir.write(
      "exp.toml", experiment_text("question = \"Which is \\\"brighter\\\"?\"\nstimulus_frames = 7",
                                  "file = \"conditions.csv\"\n"));
  const Experiment original = load_experiment(path);
  const std::string resolved = resolved_config_toml(original);
  const Experiment reread = parse_experiment_text(resolved, "<stored config>", "/");
  EXPECT_EQ(resolved_config_toml(reread), resolved);

  EXPECT_EQ(reread.name, original.name);
  EXPECT_EQ(reread.seed, original.seed);
  EXPECT_EQ(reread.forced_choice.question, "Which is \"brighter\"?");
  EXPECT_EQ(reread.forced_choice.stimulus_frames, 7);
  EXPECT_EQ(reread.display.pixel_pitch_mm, original.display.pixel_pitch_mm);
  EXPECT_EQ(reread.display.gamma, original.display.gamma);
  ASSERT_EQ(reread.scenes.size(), original.scenes.size());
  for (const auto& [name, scene] : original.scenes) {
    EXPECT_EQ(reread.scenes.at(name).file, scene.file);
    EXPECT_EQ(reread.scenes.at(name).scale_cd_m2, scene.scale_cd_m2);
  }
  ASSERT_EQ(reread.conditions.size(), original.conditions.size());
  for (std::size_t i = 0; i < original.conditions.size(); ++i) {
    EXPECT_EQ(reread.conditions[i].fields, original.conditions[i].fields);
    EXPECT_EQ(reread.conditions[i].number, original.conditions[i].number);
  }
  EXPECT_EQ(*reread.conditions[0].find("note"), "multi\nline");
  EXPECT_EQ(reread.source_file, "<stored config>");
}

// [observer] age_years and pigmentation: the observer's eye of the analytic glare models, in the
// glare spec (where the glare stage reads it), 25 years and 0.5 when absent, stored and read back.
TEST(ExperimentFile, ObserverEyeIsReadIntoTheGlareSpecAndStored) {
  test::ScratchDir dir;
  dir.write("conditions.csv", kCsv);
  const Experiment defaults = load_experiment(dir.write("plain.toml", experiment_text("", "file = \"conditions.csv\"\n")));
  EXPECT_EQ(defaults.glare.observer_eye.age_years, 25.0);
  EXPECT_EQ(defaults.glare.observer_eye.pigmentation, 0.5);

  const std::string path = dir.write("exp.toml", experiment_text("", "file = \"conditions.csv\"\n") +
                                                     "[observer]\nage_years = 71.5\npigmentation = 0.9\n"
                                                     "[observer.simulated]\nslope = 2\n");
  const Experiment original = load_experiment(path);
  EXPECT_EQ(original.glare.observer_eye.age_years, 71.5);
  EXPECT_EQ(original.glare.observer_eye.pigmentation, 0.9);
  EXPECT_EQ(original.simulated_observer.slope, 2.0);
  const std::string resolved = resolved_config_toml(original);
  EXPECT_NE(resolved.find("age_years = 71.5"), std::string::npos) << resolved;
  const Experiment reread = parse_experiment_text(resolved, "<stored config>", "/");
  EXPECT_EQ(reread.glare.observer_eye.age_years, 71.5);
  EXPECT_EQ(reread.glare.observer_eye.pigmentation, 0.9);
  EXPECT_EQ(resolved_config_toml(reread), resolved);
  // The defaults are written too, so a later version's defaults cannot change a stored session.
  EXPECT_NE(resolved_config_toml(defaults).find("age_years = 25"), std::string::npos);
}

TEST(ExperimentFile, ObserverEyeOutOfRangeNamesFileLineColumnAndKey) {
  test::ScratchDir dir;
  dir.write("conditions.csv", kCsv);
  const std::string base = experiment_text("", "file = \"conditions.csv\"\n");  // [observer] goes on line 16
  const std::string young = dir.write("young.toml", base + "[observer]\nage_years = 0.5\n");
  EXPECT_EQ(error_of(young), young + ":17:13: key 'observer.age_years': must be from 1 to 100 years, found 0.5");
  const std::string old = dir.write("old.toml", base + "[observer]\nage_years = 101\n");
  EXPECT_EQ(error_of(old), old + ":17:13: key 'observer.age_years': must be from 1 to 100 years, found 101");
  const std::string pigment = dir.write("pigment.toml", base + "[observer]\nage_years = 30\npigmentation = 1.5\n");
  EXPECT_EQ(error_of(pigment), pigment + ":18:16: key 'observer.pigmentation': must be from 0 to 1, found 1.5");
  const std::string text = dir.write("text.toml", base + "[observer]\npigmentation = \"blue\"\n");
  EXPECT_NE(error_of(text).find(text + ":17:16: key 'observer.pigmentation'"), std::string::npos) << error_of(text);
  const std::string typo = dir.write("typo.toml", base + "[observer]\nage = 30\n");
  EXPECT_NE(error_of(typo).find(typo + ":17:1: key 'observer.age'"), std::string::npos) << error_of(typo);
}

// Column names that are not bare TOML keys (a single quote, a tab, a double quote) are written
// quoted in the stored config and read back to the same fields (the experiment_file fuzz target
// found a column named g'are that the stored config wrote bare, so a session could not resume).
TEST(ExperimentFile, ResolvedConfigReadsBackColumnNamesThatNeedQuoting) {
  test::ScratchDir dir;
  dir.write("conditions.csv",
            "name,scene_a,scene_b,g'are,\"tab\there\",\"say \"\"hi\"\"\",x'\n"
            "one,dim,bright,control,a,b,c\n");
  const std::string path = dir.write("exp.toml", experiment_text("", "file = \"conditions.csv\"\n"));
  const Experiment original = load_experiment(path);
  const std::string resolved = resolved_config_toml(original);
  const Experiment reread = parse_experiment_text(resolved, "<stored config>", "/");
  ASSERT_EQ(reread.conditions.size(), 1u);
  EXPECT_EQ(reread.conditions[0].fields, original.conditions[0].fields);
  EXPECT_EQ(*reread.conditions[0].find("g'are"), "control");
  EXPECT_EQ(*reread.conditions[0].find("tab\there"), "a");
  EXPECT_EQ(*reread.conditions[0].find("say \"hi\""), "b");
  EXPECT_EQ(resolved_config_toml(reread), resolved);
}

TEST(ExperimentFile, UnknownKeyWithSuggestion) {
  test::ScratchDir dir;
  dir.write("conditions.csv", kCsv);
  const std::string path =
      dir.write("exp.toml", experiment_text("stimulus_frame = 20", "file = \"conditions.csv\"\n"));
  EXPECT_EQ(error_of(path), path +
                                ":12:1: key 'procedure.stimulus_frame': unknown key 'stimulus_frame' in [procedure] "
                                "(did you mean 'stimulus_frames'?; allowed: type, alternatives, layout, question, "
                                "stimulus_frames, stimulus_duration_s, repetitions, counterbalance_sides, design, block_order, "
            "participant_number, responses)");
}

TEST(ExperimentFile, UnknownTopLevelTable) {
  const std::string text = "[experiment]\nname = \"x\"\n[procedur]\ntype = \"forced_choice\"\n";
  try {
    parse_experiment_text(text, "m.toml", "/");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "procedur");
    EXPECT_EQ(error.where().to_string(), "m.toml:3:2");
    EXPECT_NE(std::string(error.what()).find("did you mean 'procedure'?"), std::string::npos);
  }
}

TEST(ExperimentFile, WrongType) {
  test::ScratchDir dir;
  dir.write("conditions.csv", kCsv);
  const std::string path =
      dir.write("exp.toml", experiment_text("stimulus_frames = \"thirty\"", "file = \"conditions.csv\"\n"));
  EXPECT_EQ(error_of(path), path + ":12:19: key 'procedure.stimulus_frames': expected an integer, found a string");
}

TEST(ExperimentFile, RangeChecksAndUnsupportedProcedure) {
  test::ScratchDir dir;
  dir.write("conditions.csv", kCsv);
  const auto check = [&](const std::string& extra, const std::string& expected) {
    const std::string path = dir.write("exp.toml", experiment_text(extra, "file = \"conditions.csv\"\n"));
    EXPECT_EQ(error_of(path), path + expected) << extra;
  };
  check("stimulus_frames = 0", ":12:19: key 'procedure.stimulus_frames': must be >= 1, found 0");
  check("alternatives = 4", ":12:16: key 'procedure.alternatives': must be 2 or 3 (two sources, optionally 'neither'), found 4");
  check("responses = [\"a\", \"a\"]", ":12:19: key 'procedure.responses[1]': duplicate response 'a'");
  check("responses = [\"a\"]",
        ":12:13: key 'procedure.responses': expected 2 distinct responses (one per alternative), found 1");
  check("layout = \"stacked\"", ":12:10: key 'procedure.layout': unsupported layout 'stacked' (supported: 'side_by_side', 'sequential')");

  const std::string path = dir.write(
      "exp.toml", "[experiment]\nname = \"x\"\n[scenes]\na = { file = \"a.exr\" }\n[procedure]\ntype = \"method_of_limits\"\n");
  EXPECT_EQ(error_of(path), path + ":6:8: key 'procedure.type': unsupported procedure 'method_of_limits' (supported: "
                                   "'forced_choice', 'staircase', 'quest', 'quest_plus', 'psi', 'rating', 'adjustment', "
                                   "'straylight')");

  const std::string display = dir.write("exp.toml", "[experiment]\nname = \"x\"\n[display]\nencoding = \"hlg\"\n");
  EXPECT_EQ(error_of(display), display + ":4:12: key 'display.encoding': unsupported encoding 'hlg' (supported: 'srgb', "
                                         "'gamma', 'pq', 'table')");
  const std::string lapse = dir.write("exp.toml", experiment_text("", "file = \"conditions.csv\"\n") +
                                                      "[observer.simulated]\nlapse = 0.5\n");
  EXPECT_EQ(error_of(lapse), lapse + ":17:9: key 'observer.simulated.lapse': must be in [0, 0.5), found 0.5");
}

TEST(ExperimentFile, MissingTomlFile) {
  test::ScratchDir dir;
  const std::string path = (dir.path() / "absent.toml").string();
  EXPECT_EQ(error_of(path), path + ": file not found");
}

TEST(ExperimentFile, SyntaxErrorHasLocation) {
  try {
    parse_experiment_text("[experiment]\nname = = 3\n", "bad.toml", "/");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.where().to_string(), "bad.toml:2:8");
    EXPECT_NE(error.message().find("TOML syntax error"), std::string::npos);
  }
}

TEST(ExperimentFile, MissingCsvFileIsReportedAtTheFileKey) {
  test::ScratchDir dir;
  const std::string path = dir.write("exp.toml", experiment_text("", "file = \"absent.csv\"\n"));
  EXPECT_EQ(error_of(path), path + ":15:1: key 'conditions.file': condition table '" +
                                (dir.path() / "absent.csv").string() + "': file not found");
}

TEST(ExperimentFile, MissingCsvColumn) {
  test::ScratchDir dir;
  const std::string csv = dir.write("conditions.csv", "name,scene_a\nx,dim\n");
  const std::string path = dir.write("exp.toml", experiment_text("", "file = \"conditions.csv\"\n"));
  EXPECT_EQ(error_of(path), csv + ":1:1: key 'scene_b': missing column 'scene_b' in " + csv +
                                " (columns: 'name', 'scene_a')");
}

TEST(ExperimentFile, UnknownSceneInCsvCell) {
  test::ScratchDir dir;
  const std::string csv = dir.write("conditions.csv", "name,scene_a,scene_b\nok,dim,bright\nbad, dim ,brite\n");
  const std::string path = dir.write("exp.toml", experiment_text("", "file = \"conditions.csv\"\n"));
  EXPECT_EQ(error_of(path), csv + ":3:11: key 'scene_b': unknown scene 'brite' (scenes in [scenes]: 'bright', 'dim')");
}

TEST(ExperimentFile, UnknownSceneInInlineRow) {
  test::ScratchDir dir;
  const std::string path = dir.write(
      "exp.toml", experiment_text("", "rows = [ { scene_a = \"dim\", scene_b = \"nope\" } ]\n"));
  EXPECT_EQ(error_of(path), path + ":15:39: key 'scene_b': unknown scene 'nope' (scenes in [scenes]: 'bright', 'dim')");
}

TEST(ExperimentFile, BothFileAndRows) {
  test::ScratchDir dir;
  dir.write("conditions.csv", kCsv);
  const std::string path = dir.write(
      "exp.toml", experiment_text("", "file = \"conditions.csv\"\n[[conditions.rows]]\nscene_a = \"dim\"\n"
                                      "scene_b = \"bright\"\n"));
  EXPECT_EQ(error_of(path), path + ":16:14: key 'conditions.rows': give either 'file' (a CSV table) or 'rows' "
                                   "(inline rows), not both");
}

TEST(ExperimentFile, MissingRequiredPieces) {
  try {
    parse_experiment_text("[experiment]\nname = \"x\"\n", "m.toml", "/");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_STREQ(error.what(), "m.toml:1:1: key 'scenes': missing required table [scenes]");
  }
  try {
    parse_experiment_text("[experiment]\nseed = -1\n", "m.toml", "/");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "experiment.name");
  }
}

}  // namespace
}  // namespace glarelab
