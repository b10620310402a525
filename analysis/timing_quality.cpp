#include "analysis/timing_quality.h"

#include <algorithm>
#include <cmath>

#include "analysis/statistics.h"

namespace glarelab::analysis {

TimingQuality analyse_timing(const LoadedData& data) {
  TimingQuality quality;
  for (const LoadedSession& session : data.sessions) {
    SessionTiming timing;
    timing.label = session.label;
    timing.status = session.record.status;
    timing.clock = session.record.clock;
    timing.trials = static_cast<long>(session.trials.size());
    std::vector<double> onset_errors;
    std::vector<double> intervals;
    for (const LoadedTrial& trial : session.trials) {
      const bool timing_test = trial.record.procedure == "timing_test";
      timing.timing_test = timing.timing_test || timing_test;
      if (trial.record.response_time_s) quality.response_times_s.push_back(*trial.record.response_time_s);
      // Frames in flip order; stimulus frames have frame_index >= 0, the trial's other flips
      // (screens, fixation, intervals between, response, feedback) negative ones. Frame intervals
      // run over every flip: each one is a refresh of the display.
      for (std::size_t f = 0; f < trial.frames.size(); ++f) {
        const FrameRecord& frame = trial.frames[f];
        if (frame.frame_index >= 0) ++timing.frames;
        timing.dropped += frame.dropped ? 1 : 0;
        if (frame.frame_index == 0) onset_errors.push_back(frame.flip_s - frame.scheduled_s);
        if (f == 0) continue;
        intervals.push_back(frame.flip_s - trial.frames[f - 1].flip_s);
        if (timing_test) {
          timing.flip_intervals_s.push_back(intervals.back());
          timing.interval_dropped.push_back(frame.dropped);
        }
      }
    }
    if (!onset_errors.empty()) {
      timing.onset_jitter_sd_s = standard_deviation(onset_errors);
      double worst = 0.0;
      for (double error : onset_errors) worst = std::max(worst, std::abs(error));
      timing.onset_jitter_max_abs_s = worst;
    }
    if (!intervals.empty()) {
      timing.frame_interval_mean_s = mean_and_standard_error(intervals).mean;
      timing.frame_interval_sd_s = standard_deviation(intervals);
    }
    quality.sessions.push_back(timing);
  }
  if (!quality.response_times_s.empty()) {
    quality.response_time_median_s = median(quality.response_times_s);
    quality.response_time_mean_s = mean_and_standard_error(quality.response_times_s).mean;
  }
  return quality;
}

}  // namespace glarelab::analysis
