#pragma once
// Eye gaze from a headset's own eye tracker (XR_EXT_eye_gaze_interaction; docs/STEREO.md, "Eye
// gaze"): the runtime's gaze pose, located at each submitted frame's predicted display time, turned
// into a point on each eye's view image. No OpenXR types here: the OpenXR display fills these and
// the tracker seam (runner/tracker/headset_gaze_tracker.h) takes them as a tracker's samples.
#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "runner/display/openxr_clock.h"

namespace glarelab {

// A point on a view's image, normalised as a head-mounted tracker reports gaze: 0..1 from the
// image's left edge and from its top edge (either may lie outside 0..1 for a gaze off the image).
struct ViewGazePoint {
  double x = 0.0;
  double y = 0.0;
};

// The gaze direction in a view's own frame (OpenXR's: x right, y up, the view looking down -z)
// from the gaze pose's and the view's orientations in one space (unit quaternions x, y, z, w):
// the gaze looks down its own -z (XR_EXT_eye_gaze_interaction), rotated into the view by the
// inverse of the view's orientation.
std::array<double, 3> gaze_direction_in_view(const double gaze_orientation_xyzw[4], const double view_orientation_xyzw[4]);

// Where a direction in a view's frame meets its image: a projection layer maps the image linearly
// onto the tangents of the view's edges (OpenXR 1.0, XrFovf), so the point is the direction's
// tangents (x / -z, y / -z) between tan(left) and tan(right), tan(up) and tan(down). Nothing for a
// direction that does not point ahead of the view (z >= 0).
std::optional<ViewGazePoint> gaze_point_in_view(const std::array<double, 3>& direction, const ViewFieldOfView& view);

// The gaze at one submitted frame.
struct HeadsetGazeSample {
  std::chrono::steady_clock::time_point predicted;  // the frame's predicted display time, the gaze's time
  std::int64_t runtime_time_ns = 0;                 // the same on the runtime's clock (XrTime)
  // Whether the runtime located the gaze (XR_SPACE_LOCATION_ORIENTATION_VALID_BIT): an eye tracker
  // that lost the eyes (a blink, a slipped headset) reports no orientation, and no point is made then.
  bool tracked = false;
  // Per view, left eye first; nothing where the gaze does not point ahead of that view.
  std::optional<ViewGazePoint> views[2];
};

// A display whose runtime has an eye tracker (the OpenXR display on a system with
// XR_EXT_eye_gaze_interaction).
class HeadsetGazeSource {
 public:
  virtual ~HeadsetGazeSource() = default;
  // Whether the system has an eye tracker whose gaze the display locates.
  virtual bool has_eye_gaze() const = 0;
  // While on, every submitted frame's gaze is kept for take_eye_gaze(); off drops what is kept.
  virtual void keep_eye_gaze(bool keep) = 0;
  // The gaze of the frames submitted since the last call, in order.
  virtual std::vector<HeadsetGazeSample> take_eye_gaze() = 0;
  // "'Monado: Remote HMD' through XR_EXT_eye_gaze_interaction" for the tracker's description.
  virtual std::string eye_gaze_description() const = 0;
};

}  // namespace glarelab
