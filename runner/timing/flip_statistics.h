#pragma once
// The figures of a timing test (docs/TIMING.md), after Psychtoolbox's VBLSyncTest: the intervals
// between successive flip stamps against the nominal refresh period (mean, SD, extremes), missed
// deadlines (an interval over 1.5 periods: at least one refresh passed without a new frame, the
// rule runner/session/frame_timing.h applies to sessions), and three per-frame costs measured on
// the monotonic clock: drawing the pattern, the present call (from the buffer swap's call to its
// return) and the loop's own work between a swap's return and the next frame's drawing.
#include <string>
#include <vector>

namespace glarelab {

struct Percentiles {
  double p50_s = 0.0;
  double p99_s = 0.0;
  double max_s = 0.0;
};
// Nearest-rank percentiles (the smallest value with at least p % of the values at or below it).
Percentiles percentiles(std::vector<double> values_s);

struct FlipTimingFigures {
  long frames = 0;
  double nominal_period_s = 0.0;
  double interval_mean_s = 0.0;
  double interval_sd_s = 0.0;  // sample SD (n - 1)
  double interval_min_s = 0.0;
  double interval_max_s = 0.0;
  long missed_deadlines = 0;
  Percentiles draw;
  Percentiles present_call;
  Percentiles loop_overhead;
  // The log and terminal lines.
  std::string describe() const;
};

// `flip_s`: the flips' stamps on the session clock, in order; the per-frame costs in seconds.
// `missed` is counted by the caller with the session's rule (FrameTimingMonitor).
FlipTimingFigures flip_timing_figures(const std::vector<double>& flip_s, double refresh_hz, long missed,
                                      const std::vector<double>& draw_s, const std::vector<double>& present_call_s,
                                      const std::vector<double>& loop_overhead_s);

}  // namespace glarelab
