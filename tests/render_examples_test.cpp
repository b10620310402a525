// glarelab render shows exactly the frame a session shows: for every condition of every shipped
// example, the rendered EXR equals the first stimulus frame (after glare, with the question) of
// the first trial of that condition in a seeded session of the same file, as the session itself
// wrote it (run --save-frames). Every condition is rendered in one pass (--all-conditions), and the
// condition the session shows last alone as well (--condition), the preview that stops at its
// frame. The session computes every glare frame of the trials before; the preview only records
// them in the eye: equal frames show the eye history is carried over exactly. The session stops
// after the last trial the render names (--stop-after): spencer_staircase shows its 24 conditions
// for the first time within its first 108 of 192 trials. Each example is copied with every stimulus
// two frames long (tests/example_copies.h): the eye's history still spans every trial before the
// one compared, for a fraction of the dynamic glare frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>
#include <string>

#include "cli_process.h"
#include "core/exr_io.h"
#include "example_copies.h"
#include "protocols/experiment.h"
#include "runner/store/result_store.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {


class RenderMatchesSession : public ::testing::TestWithParam<std::string> {};

// Index of the first trial of `name` in the session, from each trial's stored condition JSON.
int first_trial_of(const std::vector<TrialRecord>& trials, const std::string& name) {
  for (const TrialRecord& trial : trials)
    if (trial.condition.find("\"name\":\"" + name + "\"") != std::string::npos) return trial.trial_index;
  return -1;
}

TEST_P(RenderMatchesSession, EveryConditionEqualsTheSessionsFirstFrameOfIt) {
  const test::ScratchDir scratch;
  const std::string file = (test::examples_with_frames(scratch.path(), 2) / GetParam()).string();
  const auto folder = scratch.path() / "rendered";
  const test::RunOutput all =
      test::run_glarelab({"render", file, "--all-conditions", "--out-dir", folder.string()}, scratch.path());
  ASSERT_EQ(all.exit_code, 0) << all.output;
  // The session runs as far as the last trial the render names, and no further: the trials after
  // it show no condition for the first time (a wrong name is still seen below: a trial named too
  // early is then a trial the session's record lacks or shows another condition in, one named too
  // late a trial the record shows the condition before).
  int last_named = -1;
  const std::regex named("condition '[^']*', trial ([0-9]+) \\(");
  for (auto it = std::sregex_iterator(all.output.begin(), all.output.end(), named); it != std::sregex_iterator(); ++it)
    last_named = std::max(last_named, std::stoi((*it)[1]));
  ASSERT_GE(last_named, 0) << all.output;

  const auto db = scratch.path() / "session.db";
  const auto frames = scratch.path() / "frames";
  const test::RunOutput session =
      test::run_glarelab({"run", file, "--display", "offscreen", "--observer", "simulated", "--db", db.string(),
                          "--save-frames", frames.string(), "--stop-after", std::to_string(last_named + 1)},
                         scratch.path());
  ASSERT_EQ(session.exit_code, 0) << session.output;
  const ResultStore store(db.string());
  const std::vector<TrialRecord> trials = store.load_trials(store.load_sessions().at(0).id);

  const Experiment experiment = load_experiment(file);
  ASSERT_FALSE(experiment.conditions.empty());
  const auto expect_frame_shown = [&](const std::string& condition, const std::filesystem::path& rendered_file,
                                      const std::string& output) {
    SCOPED_TRACE("condition " + condition);
    const int trial = first_trial_of(trials, condition);
    ASSERT_GE(trial, 0) << "the session shows no trial of the condition";
    // The render names the trial it shows: the session's first of this condition.
    std::smatch match;
    ASSERT_TRUE(std::regex_search(output, match, std::regex("condition '" + condition + "', trial ([0-9]+) \\(")))
        << output;
    EXPECT_EQ(std::stoi(match[1]), trial) << output;

    char name[32];
    std::snprintf(name, sizeof name, "trial_%04d.exr", trial);
    const ImageRGBA shown = read_exr((frames / name).string()).image;
    const ImageRGBA rendered = read_exr(rendered_file.string()).image;
    ASSERT_EQ(rendered.width_px, shown.width_px);
    ASSERT_EQ(rendered.height_px, shown.height_px);
    double peak = 0.0, largest_difference = 0.0;
    for (std::size_t i = 0; i < shown.rgba.size(); ++i) {
      peak = std::max(peak, std::abs(static_cast<double>(shown.rgba[i])));
      largest_difference = std::max(largest_difference, std::abs(static_cast<double>(shown.rgba[i]) - rendered.rgba[i]));
    }
    EXPECT_GT(peak, 0.0);
    EXPECT_EQ(largest_difference, 0.0) << "peak " << peak << " cd/m2";
  };

  EXPECT_NE(all.output.find(std::to_string(experiment.conditions.size()) + " of " +
                            std::to_string(experiment.conditions.size()) + " conditions written"),
            std::string::npos)
      << all.output;
  std::string shown_last;
  int last_trial = -1;
  for (const ConditionRow& row : experiment.conditions) {
    expect_frame_shown(row.name(), folder / (row.name() + ".exr"), all.output);
    EXPECT_TRUE(std::filesystem::is_regular_file(folder / (row.name() + ".png"))) << row.name();
    if (first_trial_of(trials, row.name()) > last_trial) {
      last_trial = first_trial_of(trials, row.name());
      shown_last = row.name();
    }
  }

  const auto alone = scratch.path() / "alone.exr";
  const test::RunOutput render =
      test::run_glarelab({"render", file, "--condition", shown_last, "--out", alone.string()}, scratch.path());
  ASSERT_EQ(render.exit_code, 0) << render.output;
  expect_frame_shown(shown_last, alone, render.output);
}

INSTANTIATE_TEST_SUITE_P(Examples, RenderMatchesSession,
                         ::testing::Values("demo.toml", "spencer_staircase.toml", "luidolt_ratings.toml",
                                           "ritschel_2afc.toml", "ritschel_adjustment.toml"),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return param.param.substr(0, param.param.find('.'));
                         });

}  // namespace
}  // namespace glarelab
