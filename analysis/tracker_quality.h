#pragma once
// Eye-tracker quality per session: the fraction of valid samples, blinks (runs of invalid
// samples of one eye lasting 50 to 500 ms, the range of blink durations in Holmqvist et al.
// 2011, "Eye Tracking", Sec. 5.4; shorter gaps are dropouts, longer ones lost tracking), and
// the pupil diameter over time aligned to each trial's onset (mean over trials and eyes in
// 50 ms bins from -0.5 s to +2 s).
#include <optional>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"

namespace glarelab::analysis {

struct PupilTrace {
  std::vector<double> time_from_onset_s;  // bin centres
  std::vector<std::optional<double>> pupil_diameter_mm;  // empty bin: no valid sample
};

// Gaze-to-flip latency of live gaze-contingent glare: the age, at each stimulus frame's flip, of
// the gaze sample its glare window was placed at (frames.gaze_age_s).
struct GazeLatency {
  long frames = 0;
  double median_ms = 0.0;
  double p95_ms = 0.0;  // nearest-rank 95th percentile
  double max_ms = 0.0;
};

struct SessionTracker {
  std::string label;
  long samples = 0;
  long valid = 0;
  long blinks = 0;
  PupilTrace pupil;
  std::optional<GazeLatency> gaze_latency;  // empty: no live glare frame used a gaze
  double valid_fraction() const { return samples > 0 ? static_cast<double>(valid) / static_cast<double>(samples) : 0.0; }
};

struct TrackerQuality {
  std::vector<SessionTracker> sessions;  // only sessions with samples
};

TrackerQuality analyse_tracker(const LoadedData& data);

}  // namespace glarelab::analysis
