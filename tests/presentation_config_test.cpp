// The [presentation] table: defaults, frames or seconds, the sequential layout's responses, the
// resolved configuration reading back to the same experiment, and errors at file:line:column.
#include <gtest/gtest.h>

#include "protocols/experiment.h"
#include "protocols/stimulus_duration.h"

namespace glarelab {
namespace {

// [presentation] starts on line 16, so its first key is on line 17.
std::string experiment_text(const std::string& presentation, const std::string& procedure_extra = "") {
  return "[experiment]\n"                                    // 1
         "name = \"presentation\"\n"                         // 2
         "\n"                                                // 3
         "[display]\n"                                       // 4
         "refresh_hz = 60.0\n"                               // 5
         "peak_luminance_cd_m2 = 200.0\n"                    // 6
         "\n"                                                // 7
         "[scenes]\n"                                        // 8
         "a = { file = \"/abs/a.exr\" }\n"                   // 9
         "b = { file = \"/abs/b.exr\" }\n"                   // 10
         "\n"                                                // 11
         "[procedure]\n"                                     // 12
         "type = \"forced_choice\"\n"                        // 13
         + procedure_extra + "\n"                            // 14
         "\n"                                                // 15
         "[presentation]\n"                                  // 16
         + presentation + "\n"                               // 17...
         "\n"
         "[conditions]\n"
         "rows = [ { scene_a = \"a\", scene_b = \"b\" } ]\n";
}

Experiment parse(const std::string& presentation, const std::string& procedure_extra = "") {
  return parse_experiment_text(experiment_text(presentation, procedure_extra), "/exp/p.toml", "/exp");
}

std::string error_of(const std::string& presentation, const std::string& procedure_extra = "") {
  try {
    parse(presentation, procedure_extra);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

TEST(PresentationConfig, DefaultsAddNothingToATrial) {
  const Experiment e = parse("");
  const PresentationSpec& p = e.presentation;
  EXPECT_EQ(p.fixation.frames, 0);
  EXPECT_EQ(p.inter_stimulus.frames, 0);
  EXPECT_EQ(p.response_window_s, 0.0);
  EXPECT_EQ(p.feedback, FeedbackKind::none);
  EXPECT_TRUE(p.instructions.empty());
  EXPECT_EQ(p.break_every_trials, 0);
  EXPECT_TRUE(p.question_above_stimuli);
  EXPECT_TRUE(describe_presentation_roundings(p, 60.0).empty());
  EXPECT_EQ(e.forced_choice.layout, "side_by_side");
  EXPECT_EQ(e.forced_choice.responses, (std::vector<std::string>{"left", "right"}));
}

TEST(PresentationConfig, ReadsEveryKeyAndRoundsSecondsToFrames) {
  const Experiment e = parse(
      "instructions = \"Press Space\"\n"
      "break_every_trials = 10\n"
      "break_text = \"Rest\"\n"
      "screen_min_duration_s = 0.5\n"
      "fixation_duration_s = 0.1\n"
      "fixation_size_deg = 1.0\n"
      "isi_duration_s = 0.03\n"
      "response_window_s = 2.5\n"
      "feedback = \"text\"\n"
      "feedback_frames = 12\n"
      "feedback_correct_text = \"yes\"\n"
      "feedback_wrong_text = \"no\"\n"
      "feedback_timeout_text = \"late\"\n"
      "text_height_deg = 0.8\n"
      "text_cd_m2 = 150\n"
      "question_above_stimuli = false\n");
  const PresentationSpec& p = e.presentation;
  EXPECT_EQ(p.instructions, "Press Space");
  EXPECT_EQ(p.break_every_trials, 10);
  EXPECT_EQ(p.break_text, "Rest");
  EXPECT_EQ(p.screen_min.frames, 30);
  EXPECT_EQ(p.fixation.frames, 6);  // 0.1 s x 60 Hz
  EXPECT_EQ(p.fixation_size_deg, 1.0);
  EXPECT_EQ(p.inter_stimulus.frames, 2);  // 0.03 s x 60 Hz = 1.8 -> 2
  EXPECT_EQ(p.response_window_s, 2.5);
  EXPECT_EQ(p.feedback, FeedbackKind::text);
  EXPECT_EQ(p.feedback_duration.frames, 12);
  EXPECT_FALSE(p.feedback_duration.seconds.has_value());
  EXPECT_EQ(p.feedback_correct_text, "yes");
  EXPECT_EQ(p.feedback_wrong_text, "no");
  EXPECT_EQ(p.feedback_timeout_text, "late");
  EXPECT_EQ(p.text_height_deg, 0.8);
  EXPECT_EQ(p.text_cd_m2, 150.0);
  EXPECT_FALSE(p.question_above_stimuli);
  // Every duration given in seconds is logged with its frames and the rounding error:
  // 2 frames at 60 Hz are 33.33 ms, 3.33 ms more than the 30 ms asked for.
  const std::vector<std::string> roundings = describe_presentation_roundings(p, 60.0);
  ASSERT_EQ(roundings.size(), 3u);
  EXPECT_EQ(roundings[0], "presentation.screen_min_duration_s 0.5 s -> 30 frames = 0.5 s at 60 Hz (rounding 0 ms)");
  EXPECT_EQ(roundings[1], "presentation.fixation_duration_s 0.1 s -> 6 frames = 0.1 s at 60 Hz (rounding 0 ms)");
  EXPECT_EQ(roundings[2].rfind("presentation.isi_duration_s 0.03 s -> 2 frames = 0.0333333 s at 60 Hz (rounding 3.3333", 0),
            0u)
      << roundings[2];
}

TEST(PresentationConfig, ResolvedConfigurationReadsBackTheSameExperiment) {
  const Experiment e = parse(
      "instructions = \"Two lines\\nof instructions\"\n"
      "fixation_duration_s = 0.1\n"
      "isi_frames = 4\n"
      "response_window_s = 1.5\n"
      "feedback = \"text\"\n"
      "feedback_duration_s = 0.25\n",
      "layout = \"sequential\"");
  const std::string resolved = resolved_config_toml(e);
  const Experiment again = parse_experiment_text(resolved, "<resolved>", "/");
  EXPECT_EQ(resolved_config_toml(again), resolved);
  EXPECT_EQ(again.presentation.instructions, "Two lines\nof instructions");
  EXPECT_EQ(again.presentation.fixation.frames, 6);
  EXPECT_EQ(again.presentation.fixation.seconds, 0.1);  // written back as seconds: resuming rounds (and logs) again
  EXPECT_EQ(again.presentation.inter_stimulus.frames, 4);
  EXPECT_FALSE(again.presentation.inter_stimulus.seconds.has_value());
  EXPECT_EQ(again.presentation.feedback_duration.frames, 15);
  EXPECT_EQ(again.forced_choice.layout, "sequential");
  EXPECT_EQ(again.forced_choice.responses, (std::vector<std::string>{"first", "second"}));
}

TEST(PresentationConfig, SequentialLayoutAnswersFirstOrSecond) {
  EXPECT_EQ(parse("", "layout = \"sequential\"\nalternatives = 3").forced_choice.responses,
            (std::vector<std::string>{"first", "second", "neither"}));
  // Named responses still work in either layout.
  EXPECT_EQ(parse("", "layout = \"sequential\"\nresponses = [\"f\", \"j\"]").forced_choice.responses,
            (std::vector<std::string>{"f", "j"}));
}

TEST(PresentationConfig, BadValuesNameFileLineAndKey) {
  EXPECT_EQ(error_of("fixation_frames = -1"),
            "/exp/p.toml:17:19: key 'presentation.fixation_frames': must be >= 0, found -1");
  EXPECT_EQ(error_of("isi_duration_s = 0.001"),
            "/exp/p.toml:17:18: key 'presentation.isi_duration_s': 0.001 s is shorter than one frame "
            "(16.6667 ms at 60 Hz)");
  EXPECT_EQ(error_of("fixation_frames = 3\nfixation_duration_s = 0.05"),
            "/exp/p.toml:18:1: key 'presentation.fixation_duration_s': give either fixation_frames or "
            "fixation_duration_s, not both");
  EXPECT_EQ(error_of("feedback = \"sound\""),
            "/exp/p.toml:17:12: key 'presentation.feedback': unsupported feedback 'sound' (supported: 'none', 'text')");
  EXPECT_EQ(error_of("feedback_frames = 0"),
            "/exp/p.toml:17:19: key 'presentation.feedback_frames': must be >= 1, found 0");
  EXPECT_EQ(error_of("text_cd_m2 = 300"),
            "/exp/p.toml:17:14: key 'presentation.text_cd_m2': must not exceed the display's peak_luminance_cd_m2 "
            "(200), found 300");
  EXPECT_EQ(error_of("text_height_deg = 0"),
            "/exp/p.toml:17:19: key 'presentation.text_height_deg': must be > 0, found 0");
  EXPECT_EQ(error_of("response_window_s = -1.0"),
            "/exp/p.toml:17:21: key 'presentation.response_window_s': must be >= 0 (0: unlimited), found -1");
  EXPECT_EQ(error_of("break_every_trials = -2"),
            "/exp/p.toml:17:22: key 'presentation.break_every_trials': must be >= 0 (0: no breaks), found -2");
  EXPECT_EQ(error_of("break_text = \"\""), "/exp/p.toml:17:14: key 'presentation.break_text': must not be empty");
  EXPECT_EQ(error_of("question_above = false").rfind(
                "/exp/p.toml:17:1: key 'presentation.question_above': unknown key 'question_above' in [presentation]", 0),
            0u)
      << error_of("question_above = false");
  EXPECT_EQ(error_of("fixation_frames = \"3\""),
            "/exp/p.toml:17:19: key 'presentation.fixation_frames': expected an integer, found a string");
  // A sequential trial answers from the second interval's onset: 30 + 30 frames = 1 s here.
  EXPECT_EQ(error_of("isi_frames = 30\nresponse_window_s = 0.8", "layout = \"sequential\""),
            "/exp/p.toml:18:21: key 'presentation.response_window_s': must be longer than the first interval and the "
            "inter-stimulus interval (1 s): answers count from the second interval's onset");
  EXPECT_EQ(error_of("", "layout = \"diagonal\""),
            "/exp/p.toml:14:10: key 'procedure.layout': unsupported layout 'diagonal' (supported: 'side_by_side', "
            "'sequential')");
  EXPECT_EQ(error_of("", "responses = [\"timeout\", \"x\"]"),
            "/exp/p.toml:14:14: key 'procedure.responses[0]': 'timeout' is reserved for a trial not answered within "
            "the response window");
}

TEST(PresentationConfig, AdjustmentHasNoResponseWindow) {
  const std::string text =
      "[experiment]\nname = \"adj\"\n[scenes]\nt = { file = \"/abs/t.exr\" }\nc = { file = \"/abs/c.exr\" }\n"
      "[procedure]\ntype = \"adjustment\"\n[presentation]\nresponse_window_s = 2.0\n"
      "[conditions]\nrows = [ { target = \"t\", comparison = \"c\" } ]\n";
  try {
    parse_experiment_text(text, "/exp/adj.toml", "/exp");
    FAIL() << "a response window for the adjustment task was accepted";
  } catch (const ConfigError& error) {
    EXPECT_EQ(std::string(error.what()),
              "/exp/adj.toml:9:21: key 'presentation.response_window_s': the adjustment task has no response window "
              "(it ends when the observer accepts)");
  }
}

}  // namespace
}  // namespace glarelab
