#pragma once
// The session clock of a display whose flips are predicted, not observed (OpenXR): now_s() is the
// monotonic clock's, and on_flip() returns the time the runtime predicted the frame just submitted
// will be shown (XrFrameState::predictedDisplayTime, converted to CLOCK_MONOTONIC, which is
// steady_clock on Linux). OpenXR reports no presentation time; docs/TIMING.md says how onsets in a
// headset are checked.
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"

namespace glarelab {

// A display that predicts when the frame it last presented is shown (the OpenXR display), rather
// than presenting it when present() returns.
class PredictedFlipSource {
 public:
  virtual ~PredictedFlipSource() = default;
  // nullopt before the first frame was submitted.
  virtual std::optional<std::chrono::steady_clock::time_point> predicted_display_time() const = 0;
};

// The head's pose at a frame's predicted display time, in the runtime's LOCAL reference space
// (metres; a unit quaternion x, y, z, w), as the OpenXR display located it for each frame.
struct HeadPoseSample {
  std::chrono::steady_clock::time_point predicted;
  bool valid = false;  // position and orientation both tracked or inferred
  double position_m[3] = {0.0, 0.0, 0.0};
  double orientation_xyzw[4] = {0.0, 0.0, 0.0, 1.0};
};

// A display that locates the head at each frame it submits (the OpenXR display).
class HeadPoseSource {
 public:
  virtual ~HeadPoseSource() = default;
  // The poses of the frames submitted since the last call, in order.
  virtual std::vector<HeadPoseSample> take_head_poses() = 0;
};

// A view's field of view as the runtime locates it (XrFovf, in degrees): the angles of its left,
// right, top and bottom edges from the view's axis, left and down negative (OpenXR 1.0, XrFovf).
struct ViewFieldOfView {
  double left_deg = 0.0;
  double right_deg = 0.0;
  double up_deg = 0.0;
  double down_deg = 0.0;
  double width_deg() const { return right_deg - left_deg; }
  double height_deg() const { return up_deg - down_deg; }
};

// A display whose views have fields of view of their own (the OpenXR display: each eye's view,
// located when its session began, before anything of the session is written).
class ViewFieldSource {
 public:
  virtual ~ViewFieldSource() = default;
  // One per view, in the views' order (left eye first).
  virtual std::vector<ViewFieldOfView> view_fields_of_view() const = 0;
};

class PredictedFlipClock final : public SessionClock {
 public:
  // start_offset_s lets a resumed session continue its time line after the last logged flip.
  PredictedFlipClock(const PredictedFlipSource& display, double start_offset_s = 0.0);
  double now_s() const override;
  // Throws std::logic_error when the display has predicted no flip yet.
  double on_flip() override;
  std::string name() const override { return "predicted"; }
  bool keeps_real_time() const override { return true; }
  // A steady_clock time on this clock.
  double session_s(std::chrono::steady_clock::time_point time) const;

 private:
  const PredictedFlipSource& display_;
  std::chrono::steady_clock::time_point start_;
  double start_offset_s_;
};

// The `head_poses` event of a trial: "2 frames: 0.419344 s (0.0000, 1.6000, 0.0000) m (0.00000,
// 0.00000, 0.00000, 1.00000); ...", each time the frame's flip_s (its predicted display time on
// the session clock), "untracked" where the runtime could not locate the head.
std::string describe_head_poses(const std::vector<HeadPoseSample>& poses, const PredictedFlipClock& clock);

}  // namespace glarelab
