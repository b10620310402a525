// The [procedure] keys of staircase, QUEST, adjustment and rating experiments, stimulus
// durations in seconds, and the resolved configuration of each example study.
#include <gtest/gtest.h>

#include "protocols/experiment.h"
#include "protocols/stimulus_duration.h"

namespace glarelab {
namespace {

const std::string kExamples = std::string(GLARELAB_SOURCE_DIR) + "/examples/";

std::string quest_text(const std::string& extra) {
  return R"(
[experiment]
name = "q"
[scenes]
lamp = { file = ")" + kExamples + R"(scenes/lamp_100.exr" }
[procedure]
type = "quest"
t_guess = 2.1
t_guess_sd = 0.4
method = "mean"
n_trials = 12
)" + extra + R"(
[[conditions.rows]]
name = "lamp"
reference = "lamp"
comparison = "lamp"
)";
}

// Spencer et al. 1995, section 4: one PSE staircase per row of spencer_conditions.csv (12 glare
// strengths x 2 groups), each taking the [procedure] keys, in two counterbalanced blocks.
TEST(ProcedureFile, SpencerPseTracksTakeDefaultsFromTheProcedureTable) {
  const Experiment e = load_experiment(kExamples + "spencer_staircase.toml");
  EXPECT_EQ(e.procedure, "staircase");
  EXPECT_EQ(e.forced_choice.alternatives, 3);
  EXPECT_EQ(e.forced_choice.responses, (std::vector<std::string>{"left", "right", "neither"}));
  EXPECT_EQ(e.adaptive.response_rule, AdaptiveResponseRule::pse);
  EXPECT_TRUE(e.adaptive.glare_reference_only);
  ASSERT_EQ(e.adaptive.tracks.size(), 24u);
  EXPECT_EQ(e.adaptive.tracks[0].staircase.name, "alone_01");
  EXPECT_EQ(e.adaptive.tracks[23].staircase.name, "context_12");
  EXPECT_EQ(e.adaptive.tracks[23].condition, "context_12");
  for (const AdaptiveTrackSpec& track : e.adaptive.tracks) {
    EXPECT_EQ(track.staircase.start_value, 100.0);
    EXPECT_EQ(track.staircase.step_sizes, (std::vector<double>{40.0, 20.0, 10.0}));
    EXPECT_EQ(track.staircase.step_type, StepType::lin);
    EXPECT_EQ(track.staircase.n_up, 1);
    EXPECT_EQ(track.staircase.n_down, 1);
    EXPECT_EQ(track.staircase.n_reversals, 3);
    EXPECT_EQ(track.staircase.n_trials, 8);
    EXPECT_EQ(track.staircase.min_value, 0.0);
    EXPECT_EQ(track.staircase.max_value, 200.0);
  }
  ASSERT_EQ(e.design.blocks.size(), 2u);
  EXPECT_EQ(e.design.block_order, BlockOrder::counterbalanced);
  EXPECT_EQ(e.scenes.at("disc").generated->generator, SceneGenerator::disc_annulus);
  // 0.4 s at 60 Hz is exactly 24 frames.
  EXPECT_EQ(e.forced_choice.stimulus_frames, 24);
  EXPECT_EQ(e.forced_choice.stimulus_duration_s, 0.4);
}

TEST(ProcedureFile, QuestKeysAndGuessRateFromAlternatives) {
  const Experiment e = parse_experiment_text(quest_text(""), "q.toml", "/");
  ASSERT_EQ(e.adaptive.tracks.size(), 1u);
  const QuestSpec& q = e.adaptive.tracks[0].quest;
  EXPECT_EQ(q.t_guess, 2.1);
  EXPECT_EQ(q.t_guess_sd, 0.4);
  EXPECT_EQ(q.placement, QuestPlacement::mean);
  EXPECT_EQ(q.n_trials, 12);
  EXPECT_DOUBLE_EQ(q.gamma, 0.5);  // 2 alternatives
  EXPECT_THROW(parse_experiment_text(quest_text("method = \"median\""), "q.toml", "/"), ConfigError);
  // A staircase key means nothing to QUEST.
  EXPECT_THROW(parse_experiment_text(quest_text("step_sizes = [1.0]"), "q.toml", "/"), ConfigError);
}

TEST(ProcedureFile, ResolvedConfigurationOfEveryExampleReadsBackTheSame) {
  for (const char* file : {"demo.toml", "spencer_staircase.toml", "ritschel_2afc.toml", "ritschel_adjustment.toml",
                           "luidolt_ratings.toml"}) {
    const Experiment e = load_experiment(kExamples + file);
    const std::string resolved = resolved_config_toml(e);
    const Experiment again = parse_experiment_text(resolved, "<resolved>", "/");
    EXPECT_EQ(resolved_config_toml(again), resolved) << file;
    EXPECT_EQ(again.procedure, e.procedure) << file;
  }
  const Experiment q = parse_experiment_text(quest_text(""), "q.toml", "/");
  EXPECT_EQ(resolved_config_toml(parse_experiment_text(resolved_config_toml(q), "<r>", "/")), resolved_config_toml(q));
}

TEST(ProcedureFile, DurationInSecondsRoundsToWholeFrames) {
  EXPECT_EQ(duration_to_frames(0.25, 60.0), 15);
  EXPECT_EQ(duration_to_frames(0.26, 60.0), 16);  // 15.6 frames
  EXPECT_EQ(duration_to_frames(0.1, 144.0), 14);  // 14.4 frames
  EXPECT_EQ(duration_to_frames(1.0 / 60.0, 60.0), 1);
  EXPECT_THROW(duration_to_frames(0.01, 60.0), std::invalid_argument);
  ForcedChoiceSpec spec;
  spec.stimulus_duration_s = 0.26;
  spec.stimulus_frames = 16;
  EXPECT_EQ(describe_duration_rounding(spec, 60.0),
            "stimulus_duration_s 0.26 s -> 16 frames = 0.266667 s at 60 Hz (rounding 6.66667 ms)");
  EXPECT_THROW(parse_experiment_text(quest_text("stimulus_frames = 3\nstimulus_duration_s = 0.05"), "q.toml", "/"),
               ConfigError);
}

TEST(ProcedureFile, InterleavedStaircasesNeedDistinctNames) {
  const std::string staircase = R"(
[experiment]
name = "s"
[scenes]
lamp = { file = ")" + kExamples + R"(scenes/lamp_100.exr" }
[procedure]
type = "staircase"
start_intensity = 150.0
[[procedure.staircases]]
name = "a"
[[procedure.staircases]]
name = "a"
[[conditions.rows]]
reference = "lamp"
comparison = "lamp"
)";
  try {
    parse_experiment_text(staircase, "s.toml", "/");
    FAIL() << "duplicate staircase names were accepted";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.where().line, 12);
    EXPECT_NE(std::string(error.what()).find("duplicate staircase name 'a'"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace glarelab
