#include "runner/session/frame_timing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace glarelab {

bool FrameTimingMonitor::on_flip(double flip_s, int trial_index, int frame_index) {
  bool late = false;
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
      } else if (interval_s > 1.5 * period_s_) {
        late = true;
        dropped_.push_back({trial_index, frame_index, interval_s});
      }
    }
  }
  has_previous_ = true;
  previous_flip_s_ = flip_s;
  return late;
}

std::optional<double> FrameTimingMonitor::on_timed_flip(double flip_s) {
  std::optional<double> late;
  if (has_previous_ && flip_s - previous_flip_s_ > 1.5 * period_s_) {
    late = flip_s - previous_flip_s_;
    ++timed_flips_late_;
  }
  has_previous_ = true;
  previous_flip_s_ = flip_s;
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
  return s;
}

std::string FrameTimingSummary::describe() const {
  char text[256];
  std::snprintf(text, sizeof text,
                "frames shown %lld, dropped %lld; onset jitter over %d onsets: mean %.3f ms, max %.3f ms",
                static_cast<long long>(frames_shown), static_cast<long long>(frames_dropped), onsets,
                onset_jitter_mean_ms, onset_jitter_max_ms);
  std::string line = text;
  if (timed_flips_late > 0) line += "; late flips of other timed phases " + std::to_string(timed_flips_late);
  return line;
}

}  // namespace glarelab
