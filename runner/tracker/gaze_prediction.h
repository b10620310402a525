#pragma once
// Latency compensation of gaze (off by default: [glare] gaze_latency_compensation). A gaze sample
// is old by the time the frame it steers is shown (tracker latency + preparation + the wait for the
// flip). With compensation on, the gaze is extrapolated to the flip time along a straight line
// fitted (least squares, x and y separately) to the confident samples of the last fit_window_s;
// the extrapolation is limited to max_ahead_s and the result kept on the display (0..1). During a
// fixation the fitted velocity is ~0 and the prediction is the fixation; during a saccade it leads
// the eye (the saccade's end is unknown, hence the limit).
#include <cstddef>
#include <deque>
#include <optional>

namespace glarelab {

struct GazeSample {
  double session_time_s = 0.0;
  double x = 0.0, y = 0.0;  // normalised display coordinates, origin top left
};

struct GazePredictionOptions {
  double fit_window_s = 0.05;  // samples used for the velocity (6 at 120 Hz)
  double max_ahead_s = 0.1;    // never extrapolate further than this past the newest sample
  std::size_t min_samples = 3;  // fewer: the newest sample as it is
};

class GazeTrack {
 public:
  explicit GazeTrack(GazePredictionOptions options = {}) : options_(options) {}
  // Samples in time order; older ones than the fit window are dropped.
  void add(const GazeSample& sample);
  std::optional<GazeSample> latest() const;
  // The gaze at `at_s` (session clock) by the straight-line fit; the newest sample when too few
  // samples lie in the window or at_s is not after it. The result's session_time_s is at_s.
  std::optional<GazeSample> predicted(double at_s) const;

 private:
  GazePredictionOptions options_;
  std::deque<GazeSample> samples_;
};

}  // namespace glarelab
