#pragma once
// Frame timing of a session: which flips came late, and how far stimulus onsets strayed from the
// refresh grid. A flip more than 1.5 refresh periods after the previous one means at least one
// refresh passed without a new frame: a dropped frame (the threshold PsychoPy and Psychtoolbox
// use for missed flips).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace glarelab {

struct DroppedFrame {
  int trial_index = 0;
  int frame_index = 0;   // within the trial's stimulus frames
  double interval_s = 0; // time since the previous flip
};

struct FrameTimingSummary {
  std::int64_t frames_shown = 0;   // stimulus flips
  std::int64_t frames_dropped = 0;
  std::int64_t timed_flips_late = 0;  // late flips of fixation, intervals between, feedback
  int onsets = 0;                  // trial onsets measured (those with a previous flip)
  // |onset interval - one refresh period| over the measured onsets, in ms.
  double onset_jitter_mean_ms = 0.0;
  double onset_jitter_max_ms = 0.0;
  std::string describe() const;  // one line for the log and the terminal
};

class FrameTimingMonitor {
 public:
  explicit FrameTimingMonitor(double refresh_hz) : period_s_(1.0 / refresh_hz) {}
  // Every flip of the session, in order; stimulus frames carry their trial and frame index
  // (frame_index < 0 for other flips: response screens, blanks). Returns true when this flip is
  // a stimulus frame that came late (a dropped frame).
  bool on_flip(double flip_s, int trial_index, int frame_index);
  // Flips of the other timed phases (fixation, inter-stimulus and inter-trial intervals, feedback):
  // a late one lengthens its phase. Returns, when the flip came more than 1.5 refresh periods
  // after the previous one: the interval since that flip; counted in FrameTimingSummary::timed_flips_late,
  // not as stimulus frames.
  std::optional<double> on_timed_flip(double flip_s);
  const std::vector<DroppedFrame>& dropped() const { return dropped_; }
  FrameTimingSummary summary() const;
  double period_s() const { return period_s_; }

 private:
  double period_s_;
  bool has_previous_ = false;
  double previous_flip_s_ = 0.0;
  std::int64_t frames_shown_ = 0;
  std::int64_t timed_flips_late_ = 0;
  int onsets_ = 0;
  double jitter_sum_s_ = 0.0;
  double jitter_max_s_ = 0.0;
  std::vector<DroppedFrame> dropped_;
};

}  // namespace glarelab
