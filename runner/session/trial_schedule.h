#pragma once
// What a trial shows, flip by flip, decided before it runs ([presentation], docs/PROCEDURES.md):
//   inter-trial interval -> screens (instructions, break, block text) -> fixation -> interval 1
//   [-> inter-stimulus interval -> interval 2 (sequential 2-AFC)] -> response -> feedback.
// Timed phases last exactly their number of flips. Screens last until the observer continues
// (at least screen_min flips); the response phase lasts until the answer or the response window.
// In the `frames` table, stimulus flips keep frame_index >= 0 (numbered on across the intervals of
// a sequential trial); every other flip of the trial has frame_index -1, -2, ... in flip order, and
// the trial's 'trial_phases' session event says which phase each run of them belongs to.
#include <string>
#include <vector>

#include "protocols/presentation_config.h"
#include "protocols/trial_plan.h"

namespace glarelab {

enum class FlipPhase { inter_trial, screen, fixation, interval, inter_stimulus, response, feedback };
const char* to_string(FlipPhase phase);

// One flip of the timed sequence from the fixation to the end of the last interval.
struct TimedFlip {
  FlipPhase phase = FlipPhase::fixation;
  int interval = -1;        // interval shown (0, 1) on stimulus flips, else -1
  int stimulus_frame = -1;  // frame_index of a stimulus flip (>= 0), else -1
  int frame_in_interval = -1;
};

struct ScreenText {
  std::string kind;  // "instructions", "break" or "block"
  std::string text;
};

struct TrialSchedule {
  int inter_trial_frames = 0;       // background flips after the previous trial
  std::vector<ScreenText> screens;  // shown in this order before the fixation
  std::vector<TimedFlip> timed;     // fixation, interval(s), inter-stimulus interval
  int intervals = 1;                // 2 for a sequential trial
  // Index into `timed` of the flip from which keys answer: the onset of the last interval (the
  // observer has seen both alternatives); keys before it are logged as ignored.
  std::size_t first_answer_flip = 0;
  std::size_t onset_flip = 0;       // index into `timed` of stimulus frame 0
};

// Trial 0 opens with the instructions and has no inter-trial interval before it. The schedule
// depends only on the plan, so a resumed session flips exactly as an uninterrupted one.
TrialSchedule schedule_trial(const PresentationSpec& spec, const TrialPlan& plan, bool sequential);

// "trial 3: inter-trial 2, fixation 3, interval 1 4 (frames 0-3), inter-stimulus 2, interval 2 4
// (frames 4-7), response 0, feedback 5 flips": the runs of phases in the order they flipped.
struct PhaseFlip {
  FlipPhase phase;
  int interval = -1;
  int stimulus_frame = -1;
};
std::string describe_trial_phases(int trial_index, const std::vector<PhaseFlip>& flips);

// The first `max_words` words of a screen's text on one line, "..." when cut.
std::string first_words(const std::string& text, std::size_t max_words = 8);

}  // namespace glarelab
