#pragma once
// The [presentation] table of an experiment file: what a trial shows around its stimulus and how
// long (docs/EXPERIMENT_FILES.md): instruction and break screens, the question written above the
// stimuli (as in Ritschel et al. 2009, 6.1), a fixation cross, the inter-stimulus interval, the
// response window and feedback. Durations are whole refresh periods; a duration given in seconds
// is rounded to frames and the rounding is logged by the runner.
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace glarelab {

class TableReader;
struct Experiment;

// A duration in whole frames, and the seconds the file gave when it gave seconds (the runner logs
// the rounding; the resolved configuration writes the seconds back so resuming rounds again).
struct FrameCount {
  int frames = 0;
  std::optional<double> seconds;
};

enum class FeedbackKind { none, text };

struct PresentationSpec {
  // Shown before the session's first trial, until the observer continues.
  std::string instructions;
  // A break screen before every n-th trial (trial_index a multiple of n, not the first); 0: none.
  int break_every_trials = 0;
  std::string break_text = "Take a short break. Press Space to continue.";
  // Screens (instructions, breaks, a block's text) stay at least this long; then Space or Enter
  // continues, and non-interactive observers continue at once.
  FrameCount screen_min = {60, std::nullopt};
  FrameCount fixation = {0, std::nullopt};  // fixation cross before the first interval; 0: none
  double fixation_size_deg = 0.5;           // arm length of the cross, degrees of visual angle
  // Background between the two intervals of a sequential trial and between trials; 0: none.
  FrameCount inter_stimulus = {0, std::nullopt};
  // Seconds from the trial's onset within which an answer counts; 0: unlimited. A trial without an
  // answer in time is recorded with response "timeout" and never scored as correct.
  double response_window_s = 0.0;
  FeedbackKind feedback = FeedbackKind::none;
  FrameCount feedback_duration = {30, std::nullopt};
  std::string feedback_correct_text = "correct";
  std::string feedback_wrong_text = "wrong";
  std::string feedback_timeout_text = "too slow";
  double text_height_deg = 0.6;   // line height of all text, degrees of visual angle
  double text_cd_m2 = 100.0;      // luminance of text and the fixation cross
  bool question_above_stimuli = true;  // the trial's question written above the stimuli
};

// The response recorded for a trial not answered within the response window.
inline constexpr const char* kTimeoutResponse = "timeout";

// Reads [presentation] if present (strictly). Needs [display], [procedure] already read into
// `experiment` (refresh rate, peak luminance, procedure, stimulus duration).
PresentationSpec read_presentation_section(TableReader& top, const Experiment& experiment);
// The table resolved_config_toml writes (every key explicit; durations as the file gave them).
toml::table presentation_section_toml(const PresentationSpec& spec);
// The duration_rounding event texts of every duration given in seconds.
std::vector<std::string> describe_presentation_roundings(const PresentationSpec& spec, double refresh_hz);

}  // namespace glarelab
