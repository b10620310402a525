#pragma once
// Timing quality per session from the frames table: dropped frames, onset jitter (flip of a
// trial's first frame minus its schedule), frame intervals; and response times over all trials.
#include <optional>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"

namespace glarelab::analysis {

struct SessionTiming {
  std::string label;
  std::string status;
  // The session's clock: "virtual" (each flip one refresh period after the last, whatever it cost:
  // no frame can drop) or "monotonic" (the flips as they happened: a window, or offscreen paced in
  // real time).
  std::string clock;
  long trials = 0;
  long frames = 0;
  long dropped = 0;
  std::optional<double> onset_jitter_sd_s;      // SD of first-frame (flip - scheduled)
  std::optional<double> onset_jitter_max_abs_s;
  std::optional<double> frame_interval_mean_s;
  std::optional<double> frame_interval_sd_s;
  // A `glarelab timing-test` session (its trial of procedure "timing_test", docs/TIMING.md): the
  // interval before each flip in flip order, and whether that flip missed its deadline (dropped),
  // for the report's histogram and time series.
  bool timing_test = false;
  std::vector<double> flip_intervals_s;
  std::vector<bool> interval_dropped;
};

struct TimingQuality {
  std::vector<SessionTiming> sessions;
  std::vector<double> response_times_s;  // every answered trial
  std::optional<double> response_time_median_s;
  std::optional<double> response_time_mean_s;
};

TimingQuality analyse_timing(const LoadedData& data);

}  // namespace glarelab::analysis
