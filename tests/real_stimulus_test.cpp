// Conditions whose stimulus is a physical object (scene "real:desk lamp", core/real_stimulus.h;
// Luidolt 2020, 7.2: the real desk lamp before its simulation): the spelling, the refusals at load
// (exit 2 at the cell's file:line:column, no database), the rating trials' records, and a session
// that shows the instruction instead of an image and stores the rating like any other.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "core/real_stimulus.h"
#include "instruction_frame.h"
#include "protocols/experiment.h"
#include "protocols/rating_procedure.h"
#include "runner/store/result_store.h"

namespace glarelab {
namespace {

using test::run_glarelab;
using test::ScratchDir;

const std::string kScenes = std::string(GLARELAB_SOURCE_DIR) + "/examples/scenes/";

// A small experiment of `procedure` (its [procedure] keys) and condition rows.
std::string experiment(const std::string& procedure, const std::string& rows) {
  return "[experiment]\nname = \"real-stimulus\"\nseed = 7\n"
         "[display]\nwidth_px = 640\nheight_px = 256\nviewing_distance_mm = 600.0\npixel_pitch_mm = 0.25\n"
         "peak_luminance_cd_m2 = 250.0\n"
         "[scenes]\n"
         "lamp_100 = { file = \"" + kScenes + "lamp_100.exr\" }\n"
         "lamp_130 = { file = \"" + kScenes + "lamp_130.exr\" }\n"
         "[procedure]\nstimulus_frames = 2\n" + procedure + "\n" + rows;
}

// 1-based "LINE:COLUMN" of the first occurrence of `needle` in `text`.
std::string line_column_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  if (at == std::string::npos) return "(not in the text)";
  const std::size_t line_start = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
  const long line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(at), '\n');
  return std::to_string(line) + ":" + std::to_string(at - line_start + 1);
}

// `glarelab run` of the text exits 2 naming FILE:LINE:COLUMN of `cell` and `message`, and writes
// no database.
void expect_refused_at(const std::string& text, const std::string& cell, const std::string& message) {
  const ScratchDir scratch;
  const std::string file = scratch.write("bad.toml", text);
  const auto db = scratch.path() / "bad.db";
  const auto run = run_glarelab({"run", file, "--display", "offscreen", "--observer", "simulated", "--db", db.string()},
                                scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find(file + ":" + line_column_of(text, cell) + ":"), std::string::npos)
      << "expected at " << line_column_of(text, cell) << ": " << run.output;
  EXPECT_NE(run.output.find(message), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(db)) << "nothing may be written before the input is valid";
}

TEST(RealStimulus, TheObjectIsTheTextAfterThePrefix) {
  EXPECT_TRUE(is_real_stimulus("real:desk lamp"));
  EXPECT_EQ(real_stimulus_object("real:desk lamp"), "desk lamp");
  EXPECT_EQ(real_stimulus_object("real:  desk lamp \t"), "desk lamp");
  EXPECT_TRUE(is_real_stimulus("real:"));
  EXPECT_EQ(real_stimulus_object("real:"), "");
  EXPECT_EQ(real_stimulus_object("real:   "), "");
  // Only the exact prefix: other names are scenes of [scenes].
  EXPECT_FALSE(is_real_stimulus("Real:desk lamp"));
  EXPECT_FALSE(is_real_stimulus("lamp_100"));
  EXPECT_FALSE(is_real_stimulus("unreal:lamp"));
  EXPECT_EQ(real_stimulus_object("lamp_100"), "");
  EXPECT_EQ(real_stimulus_instruction("desk lamp"), "Look at the real desk lamp, then answer.");
}

TEST(RealStimulus, ProceduresThatCannotRateItRefuseItAtItsCell) {
  const std::string message = "cannot present: a real object can only be rated";
  expect_refused_at(experiment("type = \"forced_choice\"",
                               "[[conditions.rows]]\nname = \"pair\"\nscene_a = \"lamp_100\"\n"
                               "scene_b = \"real:desk lamp\"\n"),
                    "\"real:desk lamp\"", "key 'scene_b': condition 'pair' shows a real stimulus ('real:desk lamp'), "
                                          "which forced choice " + message);
  expect_refused_at(experiment("type = \"staircase\"\nstart_intensity = 150.0\nstep_type = \"lin\"\n"
                               "step_sizes = [10.0]\nn_trials = 4",
                               "[[conditions.rows]]\nname = \"lamp\"\nreference = \"real:desk lamp\"\n"
                               "comparison = \"lamp_130\"\n"),
                    "\"real:desk lamp\"", "key 'reference': condition 'lamp' shows a real stimulus");
  expect_refused_at(experiment("type = \"quest\"\nt_guess = 2.1\nn_trials = 3",
                               "[[conditions.rows]]\nname = \"lamp\"\nreference = \"lamp_100\"\n"
                               "comparison = \"real:candle\"\n"),
                    "\"real:candle\"", "which quest " + message);
  expect_refused_at(experiment("type = \"adjustment\"",
                               "[[conditions.rows]]\nname = \"low\"\ntarget = \"real:desk lamp\"\n"
                               "comparison = \"lamp_100\"\n"),
                    "\"real:desk lamp\"", "which adjustment " + message);
}

TEST(RealStimulus, ACsvCellIsNamedByItsLineAndColumn) {
  const ScratchDir scratch;
  const std::string csv = scratch.write("conditions.csv", "name,reference,comparison\nlamp,lamp_100,lamp_130\n"
                                                          "real,real:desk lamp,lamp_130\n");
  const std::string file = scratch.write(
      "bad.toml", experiment("type = \"staircase\"\nstart_intensity = 150.0\nstep_type = \"lin\"\nstep_sizes = [10.0]\n"
                             "n_trials = 4",
                             "[conditions]\nfile = \"" + csv + "\"\n"));
  const auto db = scratch.path() / "bad.db";
  const auto run = run_glarelab({"run", file, "--display", "offscreen", "--observer", "simulated", "--db", db.string()},
                                scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  // Row 3 of the table, the second column from character 6.
  EXPECT_NE(run.output.find(csv + ":3:6: key 'reference': condition 'real' shows a real stimulus"), std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(db));
}

TEST(RealStimulus, AnObjectWithoutANameIsRefused) {
  for (const std::string scene : {"real:", "real:   "}) {
    const std::string text = experiment("type = \"rating\"\ncategories = [\"overall\"]",
                                        "[[conditions.rows]]\nname = \"real\"\nscene = \"" + scene + "\"\n");
    expect_refused_at(text, "\"real:", "key 'scene': condition 'real': '" + scene + "' names no object");
  }
}

TEST(RealStimulus, NothingThatRendersAnImageAppliesToIt) {
  const std::string rating = "type = \"rating\"\ncategories = [\"overall\"]";
  const std::string row = "[[conditions.rows]]\nname = \"real\"\nscene = \"real:desk lamp\"\n";
  expect_refused_at(experiment(rating, row + "glare = \"dynamic\"\n"), "\"dynamic\"",
                    "key 'glare': condition 'real' shows a real stimulus ('real:desk lamp'): no image is rendered, so "
                    "'glare = dynamic' cannot apply");
  expect_refused_at(experiment(rating, row + "perception = \"adaptation+tone_mapping\"\n"), "\"adaptation+",
                    "key 'perception': condition 'real' shows a real stimulus");
  // Control glare and no stages say the same as leaving the columns out.
  EXPECT_NO_THROW(parse_experiment_text(experiment(rating, row + "glare = \"control\"\nperception = \"none\"\n"),
                                        "ok.toml", "/"));
}

TEST(RealStimulus, ThePrefixAndTheRecordedColumnsAreReserved) {
  const std::string rating = "type = \"rating\"\ncategories = [\"overall\"]";
  std::string text = experiment(rating, "[[conditions.rows]]\nname = \"one\"\nscene = \"lamp_100\"\n");
  text.replace(text.find("lamp_130 = "), 8, "\"real:x\"");
  expect_refused_at(text, "\"real:x\"", "scene names starting with 'real:' are reserved");
  for (const std::string column : {"category", "stimulus"})
    expect_refused_at(experiment(rating, "[[conditions.rows]]\nname = \"one\"\nscene = \"lamp_100\"\n" + column +
                                             " = \"x\"\n"),
                      column + " = ", "column name '" + column + "' is reserved");
}

TEST(RealStimulus, RatingTrialsNameTheObjectAndRecordItAsReal) {
  const Experiment e = parse_experiment_text(
      experiment("type = \"rating\"\ncategories = [\"glare appearance\", \"overall\"]\nscale_points = 7\n"
                 "scale_anchors = [\"completely different\", \"exactly the same\"]",
                 "[[conditions.rows]]\nname = \"real\"\nscene = \"real: desk lamp\"\n"
                 "[[conditions.rows]]\nname = \"simulated\"\nscene = \"lamp_100\"\n"),
      "r.toml", "/");
  const std::vector<TrialPlan> plans = build_rating_trials(e);
  ASSERT_EQ(plans.size(), 4u);
  int real = 0;
  for (const TrialPlan& plan : plans) {
    EXPECT_EQ(plan.allowed_responses, (std::vector<std::string>{"1", "2", "3", "4", "5", "6", "7"}));
    const bool is_real = plan.condition_name == "real";
    real += is_real;
    EXPECT_EQ(plan.real_stimulus, is_real ? "desk lamp" : "");
    const std::string category = plan.condition_json.find("\"glare appearance\"") != std::string::npos
                                     ? "glare appearance" : "overall";
    EXPECT_EQ(plan.question, "Rate the " + category + " from 1 (completely different) to 7 (exactly the same)");
    EXPECT_EQ(plan.condition_json,
              is_real ? "{\"name\":\"real\",\"scene\":\"real: desk lamp\",\"category\":\"" + category +
                            "\",\"stimulus\":\"real\"}"
                      : "{\"name\":\"simulated\",\"scene\":\"lamp_100\",\"category\":\"" + category + "\"}");
  }
  EXPECT_EQ(real, 2);
  // The anchors are kept in the stored configuration and read back.
  const Experiment again = parse_experiment_text(resolved_config_toml(e), "<resolved>", "/");
  EXPECT_EQ(again.rating.scale_anchors, (std::vector<std::string>{"completely different", "exactly the same"}));
  EXPECT_EQ(resolved_config_toml(again), resolved_config_toml(e));
}

TEST(RealStimulus, ScaleAnchorsAreTwoTexts) {
  const auto text = [](const std::string& anchors) {
    return experiment("type = \"rating\"\ncategories = [\"overall\"]\nscale_anchors = " + anchors,
                      "[[conditions.rows]]\nname = \"one\"\nscene = \"lamp_100\"\n");
  };
  expect_refused_at(text("[\"only one\"]"), "[\"only one\"]", "expected two texts, what 1 and what 5 mean");
  expect_refused_at(text("[\"low\", \"\"]"), "[\"low\"", "anchor texts must not be empty");
  expect_refused_at(text("[\"low\", 7]"), "7]", "expected a string");
}

TEST(RealStimulus, ValidateListsTheRealObject) {
  const ScratchDir scratch;
  const std::string file = scratch.write(
      "real.toml", experiment("type = \"rating\"\ncategories = [\"overall\"]",
                              "[[conditions.rows]]\nname = \"real lamp\"\nscene = \"real:desk lamp\"\n"
                              "[[conditions.rows]]\nname = \"simulated lamp\"\nscene = \"lamp_100\"\n"));
  const auto run = run_glarelab({"validate", file}, scratch.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("2 condition row(s), 2 rating trials"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("  real stimulus: condition real lamp shows the real desk lamp (an instruction, no image)\n"),
            std::string::npos)
      << run.output;
}

// The instruction of a real stimulus as [presentation] draws text by default: lines 0.6 degrees
// high (2 x 600 mm x tan(0.3 deg) / 0.25 mm = 25.1 px, drawn 25 px), wrapped within 90 % of the
// 640 px width, at 100 cd/m2.
constexpr double kLineHeightPx = 25.0;
constexpr double kMaxWidthPx = 576.0;
constexpr double kTextCdM2 = 100.0;

// A session, real lamp first (fixed block), then the simulated one: the real trial's frame shows
// the instruction naming the object and no image; the answers are stored like any others.
TEST(RealStimulus, SessionShowsTheInstructionAndStoresTheRating) {
  const ScratchDir scratch;
  const std::string text =
      experiment("type = \"rating\"\ncategories = [\"overall\"]\nscale_points = 7\nblock_order = \"fixed\"",
                 "[[blocks]]\nname = \"real light\"\nconditions = [\"real lamp\"]\n"
                 "[[blocks]]\nname = \"simulation\"\nconditions = [\"simulated lamp\"]\n"
                 "[[conditions.rows]]\nname = \"real lamp\"\nscene = \"real:desk lamp\"\n"
                 "[[conditions.rows]]\nname = \"simulated lamp\"\nscene = \"lamp_100\"\n");
  const std::string file = scratch.write("real.toml", text);
  const std::string answers = scratch.write("answers.txt", "6\n2\n");
  const auto db = scratch.path() / "real.db";
  const auto frames = scratch.path() / "frames";
  const auto run = run_glarelab({"run", file, "--display", "offscreen", "--observer", "script:" + answers, "--db",
                                 db.string(), "--save-frames", frames.string()},
                                scratch.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const ResultStore store(db.string());
  const auto trials = store.load_trials(store.load_sessions().at(0).id);
  ASSERT_EQ(trials.size(), 2u);
  EXPECT_EQ(trials[0].condition, "{\"name\":\"real lamp\",\"scene\":\"real:desk lamp\",\"category\":\"overall\","
                                 "\"stimulus\":\"real\"}");
  EXPECT_EQ(trials[0].response, "6");
  EXPECT_EQ(trials[0].block, 0);
  EXPECT_EQ(trials[1].condition, "{\"name\":\"simulated lamp\",\"scene\":\"lamp_100\",\"category\":\"overall\"}");
  EXPECT_EQ(trials[1].response, "2");
  for (const TrialRecord& trial : trials) {
    EXPECT_EQ(trial.procedure, "rating");
    EXPECT_FALSE(trial.correct.has_value());
    const auto flips = store.load_frames(trial.id);
    EXPECT_EQ(std::count_if(flips.begin(), flips.end(), [](const FrameRecord& f) { return f.frame_index >= 0; }), 2)
        << "the real trial keeps its stimulus frames";
  }

  const ImageRGBA real = read_exr((frames / "trial_0000.exr").string()).image;
  const ImageRGBA simulated = read_exr((frames / "trial_0001.exr").string()).image;
  const std::string instruction = "Look at the real desk lamp, then answer.";
  EXPECT_LT(test::centred_text_mismatch_cd_m2(real, instruction, kLineHeightPx, kMaxWidthPx, kTextCdM2), 1e-3);
  // Another object's name is not what the frame shows, nor does the lamp's image show it.
  EXPECT_GT(test::centred_text_mismatch_cd_m2(real, "Look at the real candle, then answer.", kLineHeightPx, kMaxWidthPx,
                                              kTextCdM2),
            10.0);
  EXPECT_GT(test::centred_text_mismatch_cd_m2(simulated, instruction, kLineHeightPx, kMaxWidthPx, kTextCdM2), 10.0);
  // No image: nothing on the frame is brighter than the text.
  double real_peak = 0.0;
  for (std::size_t i = 0; i < real.rgba.size(); i += 4) real_peak = std::max(real_peak, static_cast<double>(real.rgba[i + 1]));
  EXPECT_LE(real_peak, kTextCdM2 * (1.0 + 1e-6));

  // glarelab render of the real condition is the session's frame.
  const auto rendered = scratch.path() / "real_render.exr";
  const auto render = run_glarelab({"render", file, "--condition", "real lamp", "--out", rendered.string()},
                                   scratch.path());
  ASSERT_EQ(render.exit_code, 0) << render.output;
  EXPECT_NE(render.output.find("trial 0 (rating), real stimulus 'desk lamp'"), std::string::npos) << render.output;
  EXPECT_EQ(read_exr(rendered.string()).image.rgba, real.rgba);
}

}  // namespace
}  // namespace glarelab
