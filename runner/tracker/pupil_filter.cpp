#include "runner/tracker/pupil_filter.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace glarelab {

double median_of(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("median_of: no values");
  const std::size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(middle), values.end());
  const double upper = values[middle];
  if (values.size() % 2 == 1) return upper;
  const double lower = *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(middle));
  return 0.5 * (lower + upper);
}

double median_absolute_deviation(const std::vector<double>& values) {
  const double median = median_of(values);
  std::vector<double> deviations;
  deviations.reserve(values.size());
  for (double value : values) deviations.push_back(std::abs(value - median));
  return median_of(std::move(deviations));
}

PupilFilter::PupilFilter(PupilFilterSettings settings) : settings_(settings) {}

void PupilFilter::add_blink(const BlinkEvent& blink) {
  if (blink.onset && !blink_topic_active_) blink_topic_onset_s_ = blink.session_time_s;
  blink_topic_active_ = blink.onset;
  if (!blink.onset) blink_topic_end_s_ = blink.session_time_s;
}

double PupilFilter::speed_threshold(const EyeState& eye) const {
  if (eye.speeds_mm_s.size() < settings_.speed_min_history) return INFINITY;
  const std::vector<double> speeds(eye.speeds_mm_s.begin(), eye.speeds_mm_s.end());
  // Kret and Sjak-Shie 2019, Eq. for the threshold: median(d') + n * MAD(d').
  const double threshold = median_of(speeds) + settings_.mad_multiplier * median_absolute_deviation(speeds);
  return std::max(threshold, settings_.min_speed_threshold_mm_s);
}

FilteredPupil PupilFilter::add(const TrackerSample& sample) {
  FilteredPupil out;
  out.session_time_s = sample.session_time_s;
  out.eye = std::clamp(sample.eye, 0, 1);
  EyeState& eye = eyes_[out.eye];
  const double t = sample.session_time_s;
  if (!sample.has_pupil) {
    // Gaze alone: neither a pupil to filter nor evidence of a blink; the eye's state is untouched.
    ++gaze_only_;
    out.eye_pupil_mm = eye.has_value ? eye.filtered_mm : settings_.initial_mm;
    out.model_pupil_mm = model_pupil_mm();
    return out;
  }
  if (blink_topic_active_ && t - blink_topic_onset_s_ > settings_.max_blink_s) {
    blink_topic_active_ = false;
    blink_topic_end_s_ = blink_topic_onset_s_ + settings_.max_blink_s;
    ++timed_out_blinks_;
  }
  const bool confident = sample.valid && sample.confidence >= settings_.min_confidence;
  const bool in_range = sample.pupil_diameter_mm >= settings_.min_mm && sample.pupil_diameter_mm <= settings_.max_mm;
  out.blink = blink_topic_active_ || !confident;

  bool accept = confident && in_range && !blink_topic_active_;
  if (accept && (t < eye.reject_until_s || t < blink_topic_end_s_ + settings_.blink_margin_s)) accept = false;
  // A gap (anything unusable) ends at the first usable sample; the next blink_margin_s are still
  // suspect (the lid opening), so the first usable sample starts that margin.
  if (!accept && !eye.in_gap && (out.blink || !in_range)) {
    eye.in_gap = true;
    eye.gap_start_s = t;
  } else if (eye.in_gap && confident && in_range && !blink_topic_active_) {
    eye.in_gap = false;
    eye.reject_until_s = t + settings_.blink_margin_s;
    accept = false;
  }
  const bool long_gap = !eye.has_value || t - eye.last_time_s > settings_.max_interpolated_gap_s;
  if (accept && !long_gap) {
    const double dt = t - eye.last_time_s;
    if (dt > 0.0) {
      const double speed = std::abs(sample.pupil_diameter_mm - eye.last_raw_mm) / dt;
      if (speed > speed_threshold(eye)) {
        accept = false;
      } else {
        eye.speeds_mm_s.push_back(speed);
        if (eye.speeds_mm_s.size() > settings_.speed_window) eye.speeds_mm_s.pop_front();
      }
    }
  }
  if (accept) {
    if (!eye.has_value) {
      eye.filtered_mm = sample.pupil_diameter_mm;
    } else {
      // First-order low-pass, exact for irregular sampling: alpha = 1 - exp(-dt / tau), tau = 1 / (2 pi fc).
      const double tau_s = 1.0 / (2.0 * std::numbers::pi * settings_.low_pass_cutoff_hz);
      const double dt = std::max(0.0, t - eye.last_time_s);
      const double alpha = long_gap ? 1.0 : 1.0 - std::exp(-dt / tau_s);
      eye.filtered_mm += alpha * (sample.pupil_diameter_mm - eye.filtered_mm);
    }
    eye.has_value = true;
    eye.last_time_s = t;
    eye.last_raw_mm = sample.pupil_diameter_mm;
  } else {
    ++rejected_;
  }
  eye.last_seen_s = t;
  out.accepted = accept;
  out.eye_pupil_mm = eye.has_value ? eye.filtered_mm : settings_.initial_mm;
  out.model_pupil_mm = model_pupil_mm();
  return out;
}

void PupilFilter::add_batch(const TrackerBatch& batch, std::vector<FilteredPupil>* out) {
  std::size_t next_blink = 0;
  for (const TrackerSample& sample : batch.samples) {
    while (next_blink < batch.blinks.size() && batch.blinks[next_blink].session_time_s <= sample.session_time_s)
      add_blink(batch.blinks[next_blink++]);
    const FilteredPupil filtered = add(sample);
    if (out != nullptr) out->push_back(filtered);
  }
  for (; next_blink < batch.blinks.size(); ++next_blink) add_blink(batch.blinks[next_blink]);
}

std::optional<double> PupilFilter::eye_pupil_mm(int eye) const {
  if (eye < 0 || eye > 1 || !eyes_[eye].has_value) return std::nullopt;
  return eyes_[eye].filtered_mm;
}

double PupilFilter::model_pupil_mm() const {
  double sum = 0.0;
  int count = 0;
  for (const EyeState& eye : eyes_) {
    if (!eye.has_value) continue;
    sum += eye.filtered_mm;
    ++count;
  }
  return count == 0 ? settings_.initial_mm : sum / count;
}

std::vector<double> interpolate_pupil_gaps(const std::vector<double>& times_s,
                                           const std::vector<std::optional<double>>& values_mm, double max_gap_s) {
  if (times_s.size() != values_mm.size()) throw std::invalid_argument("interpolate_pupil_gaps: sizes differ");
  std::vector<double> out(values_mm.size(), 0.0);
  std::optional<std::size_t> previous;
  for (std::size_t i = 0; i < values_mm.size(); ++i) {
    if (!values_mm[i]) continue;
    out[i] = *values_mm[i];
    const std::size_t gap_begin = previous ? *previous + 1 : 0;
    for (std::size_t j = gap_begin; j < i; ++j) {
      if (!previous) {
        out[j] = *values_mm[i];  // leading gap: the first known value
      } else {
        const double t0 = times_s[*previous], t1 = times_s[i];
        const double v0 = *values_mm[*previous], v1 = *values_mm[i];
        out[j] = (t1 - t0 <= max_gap_s && t1 > t0) ? v0 + (v1 - v0) * (times_s[j] - t0) / (t1 - t0) : v0;
      }
    }
    previous = i;
  }
  for (std::size_t j = previous ? *previous + 1 : 0; j < values_mm.size(); ++j)
    out[j] = previous ? *values_mm[*previous] : 0.0;
  return out;
}

}  // namespace glarelab
