#include "runner/session/frame_timing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace glarelab {

const char* late_onset_cause_name(int cause) {
  switch (cause) {
    case 0: return "glare preparation";
    case 1: return "perception stages";
    case 2: return "drawing";
    case 4: return "recording the trial";
    default: return "host stall";
  }
}

void FrameTimingMonitor::add_work(FlipWork kind, double seconds) { work_s_[static_cast<int>(kind)] += seconds; }

// Every flip: its interval kept for the median, the work since the previous one forgotten.
void FrameTimingMonitor::flipped(double flip_s) {
  if (has_previous_) intervals_s_.push_back(flip_s - previous_flip_s_);
  has_previous_ = true;
  previous_flip_s_ = flip_s;
  for (double& work : work_s_) work = 0.0;
}

bool FrameTimingMonitor::on_flip(double flip_s, int trial_index, int frame_index) {
  bool late = false;
  late_onset_.reset();
  if (frame_index >= 0) {
    ++frames_shown_;
    if (has_previous_) {
      const double interval_s = flip_s - previous_flip_s_;
      if (frame_index == 0) {
        // The onset should follow the previous flip by exactly one refresh.
        const double jitter_s = std::abs(interval_s - period_s_);
        ++onsets_;
        jitter_sum_s_ += jitter_s;
        jitter_max_s_ = std::max(jitter_max_s_, jitter_s);
        if (interval_s > 1.5 * period_s_) {
          // The kind of work that took longest since the previous flip, if it covers half the delay.
          int cause = 0;
          for (int kind = 1; kind < kLateOnsetCauses; ++kind)
            if (kind != kHostStallCause && work_s_[kind] > work_s_[cause]) cause = kind;
          if (!(work_s_[cause] >= 0.5 * (interval_s - period_s_))) cause = kHostStallCause;
          ++late_onsets_by_cause_[cause];
          late_onset_ = LateOnset{interval_s, cause, {}};
          for (int kind = 0; kind < kLateOnsetCauses; ++kind) late_onset_->work_s[kind] = work_s_[kind];
        }
      } else if (interval_s > 1.5 * period_s_) {
        late = true;
        dropped_.push_back({trial_index, frame_index, interval_s});
      }
    }
  }
  flipped(flip_s);
  return late;
}

std::optional<double> FrameTimingMonitor::on_timed_flip(double flip_s) {
  std::optional<double> late;
  late_onset_.reset();
  if (has_previous_ && flip_s - previous_flip_s_ > 1.5 * period_s_) {
    late = flip_s - previous_flip_s_;
    ++timed_flips_late_;
  }
  flipped(flip_s);
  return late;
}

FrameTimingSummary FrameTimingMonitor::summary() const {
  FrameTimingSummary s;
  s.timed_flips_late = timed_flips_late_;
  s.frames_shown = frames_shown_;
  s.frames_dropped = static_cast<std::int64_t>(dropped_.size());
  s.onsets = onsets_;
  s.onset_jitter_mean_ms = onsets_ > 0 ? 1000.0 * jitter_sum_s_ / onsets_ : 0.0;
  s.onset_jitter_max_ms = 1000.0 * jitter_max_s_;
  for (int cause = 0; cause < kLateOnsetCauses; ++cause) {
    s.late_onsets_by_cause[cause] = late_onsets_by_cause_[cause];
    s.late_onsets += late_onsets_by_cause_[cause];
  }
  if (!intervals_s_.empty()) {
    std::vector<double> sorted = intervals_s_;
    const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
    std::nth_element(sorted.begin(), middle, sorted.end());
    s.flip_interval_median_ms = 1000.0 * *middle;
  }
  return s;
}

std::string LateOnset::describe(int trial_index) const {
  char number[64];
  std::snprintf(number, sizeof number, "%.3f", 1000.0 * interval_s);
  std::string line = "trial " + std::to_string(trial_index) + " onset: " + number + " ms since the previous flip (" +
                     late_onset_cause_name(cause) + "); the session's work since that flip:";
  bool first = true;
  for (const int kind : {0, 1, 2, 4}) {
    std::snprintf(number, sizeof number, "%.3f", 1000.0 * work_s[kind]);
    line += std::string(first ? " " : ", ") + late_onset_cause_name(kind) + " " + number + " ms";
    first = false;
  }
  return line;
}

std::string FrameTimingSummary::describe() const {
  char text[256];
  std::snprintf(text, sizeof text,
                "frames shown %lld, dropped %lld; onset jitter over %d onsets: mean %.3f ms, max %.3f ms",
                static_cast<long long>(frames_shown), static_cast<long long>(frames_dropped), onsets,
                onset_jitter_mean_ms, onset_jitter_max_ms);
  std::string line = text;
  if (timed_flips_late > 0) line += "; late flips of other timed phases " + std::to_string(timed_flips_late);
  if (late_onsets > 0) {
    // What made them late (FlipWork), so a jitter figure comes with its reason.
    line += "; late onsets " + std::to_string(late_onsets) + " (";
    bool first = true;
    // The session's own work first, the host stall last.
    for (const int cause : {0, 1, 2, 4, kHostStallCause}) {
      if (late_onsets_by_cause[cause] == 0) continue;
      line += (first ? "" : ", ") + std::string(late_onset_cause_name(cause)) + " " +
              std::to_string(late_onsets_by_cause[cause]);
      first = false;
    }
    line += ")";
  }
  return line;
}

}  // namespace glarelab
