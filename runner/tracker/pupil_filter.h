#pragma once
// Robust pupil signal for the glare model, sample by sample (causal, no look-ahead, so it can run
// in the frame loop). Per eye, a sample is accepted when
//  - its confidence is at least min_confidence (Pupil Labs recommends 0.6),
//  - its diameter lies in the physiological range [min_mm, max_mm] (1.5-9 mm),
//  - no blink is in progress (tracker blink topic, or a confidence drop), nor ended less than
//    blink_margin_s ago (the lid still covers part of the pupil),
//  - its dilation speed from the last accepted sample is at most median + mad_multiplier * MAD of
//    the recent speeds (Kret and Sjak-Shie 2019, Sec. 2.2.2 "dilation speed outliers", n = 16).
// Accepted samples pass a first-order low-pass (low_pass_cutoff_hz). A rejected sample holds the
// last value: the model pupil never drops toward 0 in a blink (Luidolt 2020, 7.2 reports the
// glare flicker that raw tracker zeros cause). Interpolation needs the sample after a gap, so it
// is done offline (interpolate_pupil_gaps); online, holding is the causal equivalent.
// The model pupil is the mean of the eyes' filtered values.
#include <cstddef>
#include <deque>
#include <optional>
#include <vector>

#include "runner/tracker/tracker_source.h"

namespace glarelab {

struct PupilFilterSettings {
  double min_confidence = 0.6;
  double min_mm = 1.5;
  double max_mm = 9.0;
  double mad_multiplier = 16.0;          // Kret and Sjak-Shie 2019 default n
  std::size_t speed_window = 240;        // recent speeds for median/MAD (2 s at 120 Hz)
  std::size_t speed_min_history = 20;    // no speed rejection before this many speeds
  // Floor of the speed threshold: a perfectly steady signal has MAD 0 and would reject every change.
  double min_speed_threshold_mm_s = 5.0;
  double blink_margin_s = 0.05;          // samples this soon after a blink or gap are rejected
  // A blink onset whose offset never comes (a lost message) ends the topic's blink this long after
  // its onset. Spontaneous blinks last 0.1-0.4 s; a lid that really stays shut longer keeps the
  // samples unconfident, and the confidence test goes on treating them as a blink.
  double max_blink_s = 1.0;
  double max_interpolated_gap_s = 0.25;  // longer gaps: hold, and restart the speed reference
  double low_pass_cutoff_hz = 4.0;
  double initial_mm = 4.0;               // model pupil before the first accepted sample
};

struct FilteredPupil {
  double session_time_s = 0.0;
  int eye = 0;
  bool accepted = false;             // a pupil sample the filter took (never a gaze-only one)
  bool blink = false;                // a blink is in progress (topic or confidence)
  double eye_pupil_mm = 0.0;         // this eye's filtered value
  double model_pupil_mm = 0.0;       // mean over eyes: what the glare model gets
};

class PupilFilter {
 public:
  explicit PupilFilter(PupilFilterSettings settings = {});
  // Blink events must be given before the samples they precede (the session loop does so).
  void add_blink(const BlinkEvent& blink);
  FilteredPupil add(const TrackerSample& sample);
  // Processes a batch in order (blinks by time, interleaved with the samples); appends outputs.
  void add_batch(const TrackerBatch& batch, std::vector<FilteredPupil>* out);
  double model_pupil_mm() const;
  // One eye's filtered pupil (eye 0 or 1), nothing before that eye's first accepted sample: the
  // pupil of that eye's model in a stereo session.
  std::optional<double> eye_pupil_mm(int eye) const;
  // Whether any sample has been accepted (before that model_pupil_mm() is settings.initial_mm).
  bool has_measurement() const { return eyes_[0].has_value || eyes_[1].has_value; }
  std::size_t rejected() const { return rejected_; }
  // Samples that carried gaze alone (TrackerSample::has_pupil false), left out of the filter.
  std::size_t gaze_only() const { return gaze_only_; }
  // Blink onsets whose offset did not come within settings.max_blink_s.
  std::size_t timed_out_blinks() const { return timed_out_blinks_; }
  const PupilFilterSettings& settings() const { return settings_; }

 private:
  struct EyeState {
    bool has_value = false;
    double filtered_mm = 0.0;
    double last_time_s = 0.0;      // last accepted sample
    double last_raw_mm = 0.0;
    double last_seen_s = -1e300;   // last sample of any kind
    bool in_gap = false;
    double gap_start_s = 0.0;
    double reject_until_s = -1e300;
    std::deque<double> speeds_mm_s;
  };
  double speed_threshold(const EyeState& eye) const;

  PupilFilterSettings settings_;
  EyeState eyes_[2];
  bool blink_topic_active_ = false;
  double blink_topic_end_s_ = -1e300;
  double blink_topic_onset_s_ = 0.0;
  std::size_t rejected_ = 0;
  std::size_t gaze_only_ = 0;
  std::size_t timed_out_blinks_ = 0;
};

// Offline: linear interpolation over gaps (nullopt values) of at most max_gap_s between two known
// values; longer gaps and the ends hold the nearest known value. Times ascending.
std::vector<double> interpolate_pupil_gaps(const std::vector<double>& times_s,
                                           const std::vector<std::optional<double>>& values_mm, double max_gap_s);

// Median and median absolute deviation (MAD, unscaled) of `values` (non-empty).
double median_of(std::vector<double> values);
double median_absolute_deviation(const std::vector<double>& values);

}  // namespace glarelab
