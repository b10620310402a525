#include "runner/tracker/gaze_prediction.h"

#include <algorithm>

namespace glarelab {

void GazeTrack::add(const GazeSample& sample) {
  samples_.push_back(sample);
  while (!samples_.empty() && samples_.front().session_time_s < sample.session_time_s - options_.fit_window_s)
    samples_.pop_front();
}

std::optional<GazeSample> GazeTrack::latest() const {
  if (samples_.empty()) return std::nullopt;
  return samples_.back();
}

std::optional<GazeSample> GazeTrack::predicted(double at_s) const {
  if (samples_.empty()) return std::nullopt;
  const GazeSample& newest = samples_.back();
  if (samples_.size() < options_.min_samples || !(at_s > newest.session_time_s)) return newest;
  // Least-squares line through (t, x) and (t, y), t taken relative to the newest sample so the
  // sums stay well conditioned on a long session clock.
  double st = 0.0, sx = 0.0, sy = 0.0, stt = 0.0, stx = 0.0, sty = 0.0;
  const auto n = static_cast<double>(samples_.size());
  for (const GazeSample& s : samples_) {
    const double t = s.session_time_s - newest.session_time_s;
    st += t, sx += s.x, sy += s.y, stt += t * t, stx += t * s.x, sty += t * s.y;
  }
  const double denominator = n * stt - st * st;
  if (!(denominator > 0.0)) return newest;  // all samples at one instant
  const double vx = (n * stx - st * sx) / denominator;
  const double vy = (n * sty - st * sy) / denominator;
  const double x0 = (sx - vx * st) / n;  // the fitted position at the newest sample's time
  const double y0 = (sy - vy * st) / n;
  const double ahead_s = std::min(at_s - newest.session_time_s, options_.max_ahead_s);
  return GazeSample{at_s, std::clamp(x0 + vx * ahead_s, 0.0, 1.0), std::clamp(y0 + vy * ahead_s, 0.0, 1.0)};
}

}  // namespace glarelab
