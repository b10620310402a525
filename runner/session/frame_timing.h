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

// What the session did between a late trial onset and the flip before it, the likely cause of
// its lateness (FrameTimingSummary::late_onsets_by_cause): computing glare frames, the perception
// stages (with any glare among them), drawing and encoding the frame, or nothing of the
// session's own that took long enough: the host held the process (another program, the driver,
// the compositor, swapping). Recording is the session's writes to the results database between a
// trial's last flip and the next one's first (the trial's row and every flip's, its events), and a
// saved frame's read-back (--save-frames; its file is written beside the session).
enum class FlipWork { glare_preparation = 0, perception = 1, drawing = 2, recording = 4 };
// Late onsets' causes, indexed as FrameTimingSummary::late_onsets_by_cause: the FlipWork kinds by
// their values and the host stall at 3 (recording the trial, the last kind added, comes after it).
inline constexpr int kHostStallCause = 3;
inline constexpr int kLateOnsetCauses = 5;
const char* late_onset_cause_name(int cause);

struct FrameTimingSummary {
  std::int64_t frames_shown = 0;   // stimulus flips
  std::int64_t frames_dropped = 0;
  std::int64_t timed_flips_late = 0;  // late flips of fixation, intervals between, feedback
  int onsets = 0;                  // trial onsets measured (those with a previous flip)
  // |onset interval - one refresh period| over the measured onsets, in ms.
  double onset_jitter_mean_ms = 0.0;
  double onset_jitter_max_ms = 0.0;
  // Onsets more than 1.5 periods after the flip before them, by likely cause (indexed by FlipWork,
  // the host stall at kHostStallCause).
  int late_onsets = 0;
  int late_onsets_by_cause[kLateOnsetCauses] = {0, 0, 0, 0, 0};
  // The median interval between successive flips of any kind (0 with fewer than two flips): what
  // runner/session/refresh_rate_check.h's flip_interval_warning compares with the nominal period.
  double flip_interval_median_ms = 0.0;
  std::string describe() const;  // one line for the log and the terminal
};

// A trial's onset that came more than 1.5 periods after the flip before it (the onset itself is
// no dropped frame: no stimulus frame was lost, the blank before it lasted longer).
struct LateOnset {
  double interval_s = 0.0;  // since the previous flip
  int cause = kHostStallCause;  // as FrameTimingSummary::late_onsets_by_cause
  // The session's own work since the previous flip, by FlipWork (wall-clock seconds; the host
  // stall's entry is 0): what of the lateness the session did, the rest being the host's.
  double work_s[kLateOnsetCauses] = {0.0, 0.0, 0.0, 0.0, 0.0};
  // "trial 7 onset: 116.667 ms since the previous flip (host stall); the session's work since that
  // flip: glare preparation 0.000 ms, perception stages 0.000 ms, drawing 2.135 ms, recording the
  // trial 0.000 ms": the late_onset event.
  std::string describe(int trial_index) const;
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
  // After on_flip() of a trial's onset (frame_index 0): the onset, when it came late; empty after
  // any other flip.
  const std::optional<LateOnset>& late_onset() const { return late_onset_; }
  // Work the session did since the previous flip (wall-clock seconds), read at the next onset if it
  // comes late: the kind with most of it is the onset's cause when it covers at least half the
  // lateness (the interval less one period), else the host stalled.
  void add_work(FlipWork kind, double seconds);
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
  double work_s_[kLateOnsetCauses] = {0.0, 0.0, 0.0, 0.0, 0.0};  // since the previous flip, by FlipWork
  int late_onsets_by_cause_[kLateOnsetCauses] = {0, 0, 0, 0, 0};
  std::vector<double> intervals_s_;  // between successive flips, for the median
  std::optional<LateOnset> late_onset_;  // of the last flip
  void flipped(double flip_s);
};

}  // namespace glarelab
