// QUEST+ and Psi tracks (type = "quest_plus" / "psi") as experiment files and through the
// Procedure interface: every trial shows what the QuestPlus class (checked against Watson 2017's
// examples in quest_plus_test.cpp) chooses, tracks interleave like staircases, each trial's
// record carries the posterior it was chosen from, the stored design reads back to the same
// procedure, and a session cut off and resumed runs exactly the trials of an uninterrupted one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <filesystem>
#include <sstream>
#include <string>

#include "cli_process.h"
#include "experiment_error.h"
#include "protocols/adaptive_procedure.h"
#include "protocols/experiment.h"
#include "runner/store/result_store.h"

namespace glarelab {
namespace {

using test::run_glarelab;
using test::ScratchDir;

const std::string kExamples = std::string(GLARELAB_SOURCE_DIR) + "/examples/";

// The example study with scene paths made absolute and, when asked, lines replaced by key.
std::string example_text(const std::map<std::string, std::string>& replace = {}) {
  std::istringstream study(test::read_bytes(kExamples + "glare_quest_plus.toml"));
  std::string text, line;
  while (std::getline(study, line)) {
    for (const auto& [key, value] : replace)
      if (line == key || line.rfind(key + " ", 0) == 0) line = value;
    if (const auto at = line.find("\"scenes/"); at != std::string::npos) line.insert(at + 1, kExamples);
    text += line + "\n";
  }
  return text;
}

std::map<std::string, double> peaks_of(const Experiment& e) {
  std::map<std::string, double> peaks;
  for (const auto& [name, scene] : e.scenes) peaks[name] = name == "lamp_130" ? 130.0 : name == "lamp_160" ? 160.0 : 100.0;
  return peaks;
}

// The value of a "key":"value" member of a flat JSON object written by JsonObjectWriter.
std::string json_member(const std::string& json, const std::string& key) {
  const std::string needle = "\"" + key + "\":\"";
  const auto start = json.find(needle);
  if (start == std::string::npos) return "";
  const auto end = json.find('"', start + needle.size());
  return json.substr(start + needle.size(), end - start - needle.size());
}

bool answer_correct(int trial) { return ((trial * 7 + 3) % 5) < 3; }

std::string answer(const TrialPlan& plan, bool correct) {
  if (correct) return plan.correct_response;
  for (const std::string& r : plan.allowed_responses)
    if (r != plan.correct_response) return r;
  return "";
}

TEST(QuestPlusProcedure, ExampleFileReadsAsWritten) {
  const ScratchDir scratch;
  const Experiment e = load_experiment(scratch.write("qp.toml", example_text()));
  ASSERT_EQ(e.adaptive.tracks.size(), 2u);
  const QuestPlusTrackSpec& a = e.adaptive.tracks[0].quest_plus;
  EXPECT_EQ(a.spec.name, "threshold_slope_lapse");
  EXPECT_EQ(a.intensity_unit, "db_cd_m2");
  EXPECT_EQ(a.spec.scale, StimulusScale::db);
  ASSERT_EQ(a.spec.stimulus.size(), 1u);
  EXPECT_EQ(a.spec.stimulus[0].values.size(), 39u);  // 40.2 .. 47.8 dB in 0.2 dB
  EXPECT_NEAR(a.spec.stimulus[0].values.back(), 47.8, 1e-12);
  ASSERT_EQ(a.spec.parameters.size(), 4u);  // threshold, slope, guess (1 / alternatives), lapse
  EXPECT_EQ(a.spec.parameters[2].values, std::vector<double>{0.5});
  EXPECT_EQ(a.spec.parameters[3].values, (std::vector<double>{0.0, 0.02, 0.04}));
  EXPECT_EQ(a.spec.max_trials, 24);
  const QuestPlusTrackSpec& b = e.adaptive.tracks[1].quest_plus;
  EXPECT_EQ(b.stimulus_columns, std::vector<std::string>{"reference_gain_db"});
  ASSERT_EQ(b.spec.parameters.size(), 5u);
  EXPECT_EQ(b.spec.parameters[1].name, "threshold_per_reference_gain_db");
  EXPECT_EQ(b.spec.parameters[1].prior, (std::vector<double>{1.0, 2.0, 4.0, 2.0, 1.0}));
  EXPECT_EQ(b.spec.parameters[4].values, std::vector<double>{0.02});  // the track's own lapse

  // The resolved configuration (stored with each session) reads back to the same grids.
  const ScratchDir again;
  const Experiment back = load_experiment(again.write("resolved.toml", resolved_config_toml(e)));
  ASSERT_EQ(back.adaptive.tracks.size(), 2u);
  for (std::size_t t = 0; t < 2; ++t) {
    const QuestPlusSpec& x = e.adaptive.tracks[t].quest_plus.spec;
    const QuestPlusSpec& y = back.adaptive.tracks[t].quest_plus.spec;
    EXPECT_EQ(x.stimulus[0].values, y.stimulus[0].values);
    ASSERT_EQ(x.parameters.size(), y.parameters.size());
    for (std::size_t i = 0; i < x.parameters.size(); ++i) {
      EXPECT_EQ(x.parameters[i].name, y.parameters[i].name);
      EXPECT_EQ(x.parameters[i].values, y.parameters[i].values);
      EXPECT_EQ(x.parameters[i].prior, y.parameters[i].prior);
    }
    EXPECT_EQ(x.max_trials, y.max_trials);
  }
}

TEST(QuestPlusProcedure, TrialsFollowTheQuestPlusClassAndRecordThePosterior) {
  const ScratchDir scratch;
  const Experiment e = load_experiment(scratch.write("qp.toml", example_text()));
  AdaptiveProcedure procedure(e, peaks_of(e));
  // Stand-alone references of both tracks, given the same answers.
  std::vector<QuestPlus> reference;
  std::vector<std::vector<std::size_t>> rows;
  for (const AdaptiveTrackSpec& track : e.adaptive.tracks) {
    QuestPlusTrackGrid grid = quest_plus_track_grid(e, track);
    reference.emplace_back(grid.spec);
    rows.push_back(grid.rows);
  }
  EXPECT_EQ(rows[1].size(), 3u);
  int trial = 0;
  std::set<std::string> rows_shown;
  while (!procedure.finished()) {
    const TrialPlan plan = procedure.next_trial();
    const std::size_t t = plan.staircase == "threshold_slope_lapse" ? 0 : 1;
    ASSERT_EQ(plan.staircase, e.adaptive.tracks[t].quest_plus.spec.name);
    QuestPlus& q = reference[t];
    EXPECT_EQ(plan.procedure, "quest");
    // The comparison's peak is 10^(x / 20) cd/m2 for the intensity x in dB.
    ASSERT_TRUE(plan.intensity.has_value());
    EXPECT_NEAR(*plan.intensity, std::pow(10.0, q.next_stimulus()[0] / 20.0), 1e-9);
    const std::size_t row = rows[t][q.next_stimulus_index() % rows[t].size()];
    EXPECT_EQ(plan.condition_name, e.conditions[row].name());
    rows_shown.insert(plan.condition_name);
    EXPECT_EQ(json_member(plan.condition_json, "method"), "quest_plus");
    // Logged in full: each number reads back to exactly the value.
    EXPECT_EQ(std::stod(json_member(plan.condition_json, "intensity")), q.next_stimulus()[0]);
    EXPECT_EQ(json_member(plan.condition_json, "track_trials_done"), std::to_string(q.trial_count()));
    EXPECT_EQ(std::stod(json_member(plan.condition_json, "expected_entropy_nats")), q.next_expected_entropy());
    for (const ParameterSummary& s : q.summary()) {
      EXPECT_EQ(std::stod(json_member(plan.condition_json, "posterior_" + s.name + "_mode")), s.mode);
      EXPECT_EQ(std::stod(json_member(plan.condition_json, "posterior_" + s.name + "_mean")), s.mean);
      EXPECT_EQ(std::stod(json_member(plan.condition_json, "posterior_" + s.name + "_sd")), s.sd);
    }
    const bool correct = answer_correct(trial);
    const TrialOutcome outcome = procedure.record_response(plan, {answer(plan, correct), 0.5});
    EXPECT_EQ(outcome.correct, correct ? 1 : 0);
    EXPECT_EQ(outcome.reversal, 0);
    q.add_response(correct);
    ++trial;
  }
  EXPECT_EQ(trial, 48);
  EXPECT_EQ(reference[0].trial_count(), 24);
  EXPECT_EQ(reference[1].trial_count(), 24);
  EXPECT_GE(rows_shown.size(), 2u) << "QUEST+ chose among the reference rows";
}

TEST(QuestPlusProcedure, ReplayingResponsesReachesTheSameState) {
  const ScratchDir scratch;
  const Experiment e = load_experiment(scratch.write("qp.toml", example_text()));
  AdaptiveProcedure uninterrupted(e, peaks_of(e));
  std::vector<TrialPlan> plans;
  std::vector<Response> responses;
  for (int trial = 0; !uninterrupted.finished(); ++trial) {
    plans.push_back(uninterrupted.next_trial());
    responses.push_back({answer(plans.back(), answer_correct(trial)), 0.5});
    uninterrupted.record_response(plans.back(), responses.back());
  }
  for (std::size_t k : {std::size_t{0}, std::size_t{7}, std::size_t{31}}) {
    AdaptiveProcedure resumed(e, peaks_of(e));
    for (std::size_t i = 0; i < k; ++i) resumed.record_response(resumed.next_trial(), responses[i]);
    for (std::size_t i = k; i < plans.size(); ++i) {
      const TrialPlan plan = resumed.next_trial();
      ASSERT_EQ(plan.condition_json, plans[i].condition_json) << "after " << k << " replayed, trial " << i;
      ASSERT_EQ(plan.intensity, plans[i].intensity);
      resumed.record_response(plan, responses[i]);
    }
    EXPECT_TRUE(resumed.finished());
  }
}

TEST(QuestPlusProcedure, PsiHasItsUsualDefaults) {
  const ScratchDir scratch;
  const std::string file = scratch.write("psi.toml", R"([experiment]
name = "psi"
seed = 1999

[display]
width_px = 128
height_px = 64
refresh_hz = 60.0
viewing_distance_mm = 600.0
pixel_pitch_mm = 0.25
peak_luminance_cd_m2 = 250.0

[scenes]
lamp_100 = { file = ")" + kExamples + R"(scenes/lamp_100.exr" }

[procedure]
type = "psi"
intensities = { from = 2.0, to = 2.4, step = 0.02 }   # log10 cd/m2

[[conditions.rows]]
name = "lamp"
reference = "lamp_100"
comparison = "lamp_100"
)");
  const Experiment e = load_experiment(file);
  ASSERT_EQ(e.adaptive.tracks.size(), 1u);
  const QuestPlusTrackSpec& psi = e.adaptive.tracks[0].quest_plus;
  EXPECT_EQ(psi.spec.name, "psi");
  EXPECT_EQ(psi.intensity_unit, "log10_cd_m2");
  EXPECT_EQ(psi.spec.scale, StimulusScale::log10);
  EXPECT_EQ(psi.spec.shape, PsychometricShape::weibull);
  EXPECT_EQ(psi.spec.max_trials, 50);
  ASSERT_EQ(psi.spec.parameters.size(), 4u);
  EXPECT_EQ(psi.spec.parameters[0].values, psi.spec.stimulus[0].values);  // thresholds on the intensity grid
  EXPECT_EQ(psi.spec.parameters[1].values, psi_default_slopes());
  EXPECT_EQ(psi.spec.parameters[2].values, std::vector<double>{0.5});
  EXPECT_EQ(psi.spec.parameters[3].values, std::vector<double>{0.02});
  AdaptiveProcedure procedure(e, peaks_of(e));
  const TrialPlan plan = procedure.next_trial();
  EXPECT_EQ(json_member(plan.condition_json, "method"), "psi");
  EXPECT_EQ(json_member(plan.condition_json, "intensity_unit"), "log10_cd_m2");
  EXPECT_NEAR(*plan.intensity, std::pow(10.0, procedure.quest_plus(0)->next_stimulus()[0]), 1e-9);
  // The resolved design reads back (Psi's defaults written out).
  const Experiment back = load_experiment(scratch.write("resolved.toml", resolved_config_toml(e)));
  EXPECT_EQ(back.adaptive.tracks[0].quest_plus.spec.parameters[1].values, psi_default_slopes());
  // Psi has one stimulus dimension.
  const std::string text = test::read_bytes(file);
  const std::string two_d = text.substr(0, text.find("[[conditions.rows]]")) +
                            "stimulus_columns = [\"gain\"]\n\n" + text.substr(text.find("[[conditions.rows]]"));
  EXPECT_NE(test::experiment_error(scratch.write("psi2.toml", two_d)).find("psi has one stimulus dimension"),
            std::string::npos);
}

TEST(QuestPlusProcedure, RefusesWhatItCannotRun) {
  const ScratchDir scratch;
  auto error_of = [&](const std::map<std::string, std::string>& replace) {
    return test::experiment_error(scratch.write("bad.toml", example_text(replace)));
  };
  // Unknown keys, at their place.
  {
    const std::string text = example_text();
    const std::size_t line = static_cast<std::size_t>(std::count(text.begin(), text.begin() + text.find("max_trials"), '\n')) + 2;
    const std::string error = error_of({{"max_trials", "max_trials = 24\nmax_trial = 3"}});
    EXPECT_NE(error.find(":" + std::to_string(line) + ":1: key 'procedure.max_trial'"), std::string::npos) << error;
  }
  EXPECT_NE(error_of({{"function", "function = \"gumbel\""}}).find("unknown psychometric function 'gumbel'"),
            std::string::npos);
  EXPECT_NE(error_of({{"intensity_unit", "intensity_unit = \"cd_m2\""}}).find("unsupported intensity_unit"),
            std::string::npos);
  EXPECT_NE(error_of({{"lapse", "lapse = [0.0, 0.6]"}}).find("guess + lapse must be < 1"), std::string::npos);
  EXPECT_NE(error_of({{"slope", "slope = [2.0, -1.0]"}}).find("must be > 0"), std::string::npos);
  EXPECT_NE(error_of({{"intensities", "intensities = { from = 40.2, to = 47.8 }"}}).find("from, to and step"),
            std::string::npos);
  EXPECT_NE(error_of({{"prior", "prior = { threshold_per_reference_gain_db = [1.0, 2.0] }"}}).find("2 weights for 5"),
            std::string::npos);
  EXPECT_NE(error_of({{"prior", "prior = { thresh = [1.0] }"}}).find("no parameter named 'thresh'"),
            std::string::npos);
  EXPECT_NE(error_of({{"threshold_coefficients", "threshold_coefficients = { glare_deg = [1.0] }"}})
                .find("'glare_deg' is not one of stimulus_columns"),
            std::string::npos);
  EXPECT_NE(error_of({{"conditions", "conditions = [\"lamp_100\", \"lamp_130\", \"lamp_130\"]"}}).find("duplicate"),
            std::string::npos);
  // Two rows with the same column value: no row for every combination.
  EXPECT_NE(error_of({{"reference_gain_db = 2.279", "reference_gain_db = 0.0"}}).find("same stimulus_columns values"),
            std::string::npos);
  EXPECT_NE(error_of({{"reference_gain_db = 2.279", "reference_gain_db = \"bright\""}}).find("is not a number"),
            std::string::npos);
  EXPECT_NE(error_of({{"max_trials", "max_trials = 24\nmin_trials = 3"}}).find("only meaningful with stop_sd"),
            std::string::npos);
  EXPECT_NE(error_of({{"max_trials", "max_trials = 24\nstop_sd = 0.5\nstop_sd_parameter = \"slopes\""}})
                .find("stop_sd names no parameter 'slopes'"),
            std::string::npos);
}

TEST(QuestPlusProcedure, StopsAtThePosteriorSd) {
  const ScratchDir scratch;
  // A loose limit on the threshold's SD (dB) ends the tracks before max_trials.
  const Experiment e = load_experiment(
      scratch.write("sd.toml", example_text({{"max_trials", "max_trials = 200\nstop_sd = 1.5\nmin_trials = 3"}})));
  AdaptiveProcedure procedure(e, peaks_of(e));
  int trials = 0;
  while (!procedure.finished()) {
    const TrialPlan plan = procedure.next_trial();
    procedure.record_response(plan, {answer(plan, answer_correct(trials)), 0.5});
    ++trials;
  }
  EXPECT_LT(trials, 400);
  for (std::size_t t = 0; t < 2; ++t) {
    const QuestPlus& q = *procedure.quest_plus(t);
    EXPECT_GE(q.trial_count(), 3);
    ASSERT_EQ(q.summary()[0].name, "threshold");
    EXPECT_LE(q.summary()[0].sd, 1.5);
  }
}

// Cut off after k trials and resumed, a session shows exactly the trials of an uninterrupted one
// (the replay checks every stored condition record, posterior summary included).
TEST(QuestPlusProcedure, StopAndResumeRunsTheSameTrialsEndToEnd) {
  const ScratchDir scratch;
  const std::string file = scratch.write(
      "qp_small.toml", example_text({{"width_px", "width_px = 128"},
                                      {"height_px", "height_px = 64"},
                                      {"stimulus_duration_s", "stimulus_frames = 1"},
                                      {"max_trials", "max_trials = 8"}}));
  const std::string db = scratch.file("runs.db");
  const std::vector<std::string> base = {"run", file, "--display", "offscreen", "--observer", "simulated", "--db", db};
  // Both sessions as participant 1, so that they are the same design.
  for (const auto& extra : std::vector<std::vector<std::string>>{
           {"--participant-number", "1"}, {"--participant-number", "1", "--stop-after", "5"}, {"--resume", "2"}}) {
    std::vector<std::string> arguments = base;
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const auto result = run_glarelab(arguments, scratch.path());
    ASSERT_EQ(result.exit_code, 0) << result.output;
  }
  const ResultStore store(db);
  const auto sessions = store.load_sessions();
  ASSERT_EQ(sessions.size(), 2u);
  const auto whole = store.load_trials(sessions[0].id);
  const auto resumed = store.load_trials(sessions[1].id);
  EXPECT_EQ(sessions[1].status, "completed");
  ASSERT_EQ(whole.size(), 16u);
  ASSERT_EQ(resumed.size(), whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(resumed[i].condition, whole[i].condition) << "trial " << i;
    EXPECT_EQ(resumed[i].intensity, whole[i].intensity) << "trial " << i;
    EXPECT_EQ(resumed[i].response, whole[i].response) << "trial " << i;
    EXPECT_EQ(whole[i].procedure, "quest");
    EXPECT_FALSE(json_member(whole[i].condition, "posterior_threshold_sd").empty());
  }
}

}  // namespace
}  // namespace glarelab
