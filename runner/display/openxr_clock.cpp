#include "runner/display/openxr_clock.h"

#include <cstdio>
#include <stdexcept>

namespace glarelab {

PredictedFlipClock::PredictedFlipClock(const PredictedFlipSource& display, double start_offset_s)
    : display_(display), start_(std::chrono::steady_clock::now()), start_offset_s_(start_offset_s) {}

double PredictedFlipClock::now_s() const {
  return start_offset_s_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

double PredictedFlipClock::on_flip() {
  const std::optional<std::chrono::steady_clock::time_point> predicted = display_.predicted_display_time();
  if (!predicted) throw std::logic_error("predicted flip clock: the display has predicted no flip");
  return session_s(*predicted);
}

double PredictedFlipClock::session_s(std::chrono::steady_clock::time_point time) const {
  return start_offset_s_ + std::chrono::duration<double>(time - start_).count();
}

std::string describe_head_poses(const std::vector<HeadPoseSample>& poses, const PredictedFlipClock& clock) {
  std::string text = std::to_string(poses.size()) + (poses.size() == 1 ? " frame: " : " frames: ");
  char entry[160];
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const HeadPoseSample& pose = poses[i];
    if (pose.valid)
      std::snprintf(entry, sizeof entry, "%s%.6f s (%.4f, %.4f, %.4f) m (%.5f, %.5f, %.5f, %.5f)", i == 0 ? "" : "; ",
                    clock.session_s(pose.predicted), pose.position_m[0], pose.position_m[1], pose.position_m[2],
                    pose.orientation_xyzw[0], pose.orientation_xyzw[1], pose.orientation_xyzw[2],
                    pose.orientation_xyzw[3]);
    else
      std::snprintf(entry, sizeof entry, "%s%.6f s untracked", i == 0 ? "" : "; ", clock.session_s(pose.predicted));
    text += entry;
  }
  return text;
}

}  // namespace glarelab
