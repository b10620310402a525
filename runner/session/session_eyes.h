#pragma once
// The eyes of a session, each with what it sees of the display and the stages that make its image:
// its view (on a mono display the whole frame; with [display] stereo = "side_by_side" its half,
// stimuli/stereo_layout.h, docs/STEREO.md) and its own frame engine (stimuli/frame_engine.h: its own
// glare stage, eye model and seed, and perception eye), fed from its own tracker samples. A mono session is a
// session with one eye; the session loop's per-eye work is in runner/session/eye_glare.cpp.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/gl/gl_context.h"
#include "protocols/experiment.h"
#include "stimuli/frame_engine.h"
#include "stimuli/glare_stage.h"
#include "stimuli/scene_library.h"
#include "stimuli/session_perception.h"
#include "stimuli/stereo_layout.h"

namespace glarelab {

struct SessionEye {
  // A stereo eye: its half of the display, its model seeded by eye_seed, its tracker samples its own.
  SessionEye(const EyeView& eye_view, const Experiment& experiment, GlContextFactory gl_context);
  // The one eye of a mono display: the whole frame (`frame_width_px` x `frame_height_px`), the
  // session's seed, and the tracker's reading of both eyes together (its combined gaze, pupil and
  // blinks).
  SessionEye(const Experiment& experiment, int frame_width_px, int frame_height_px, GlContextFactory gl_context);
  EyeView view;  // mono: the whole frame, named "" (tracker_eye unused)
  // Where its pupil, blinks and gaze come from: the tracker's samples of view.tracker_eye (stereo),
  // or its binocular reading (mono).
  bool own_tracker_samples = false;
  DisplaySpec display;  // the eye's view as a display of its own
  std::uint64_t seed = 0;
  FrameEngine engine;
};

// A session's eyes: one per stereo view, left first, or the one eye of a mono display whose frame
// is `frame_width_px` x `frame_height_px`.
std::vector<std::unique_ptr<SessionEye>> make_session_eyes(const Experiment& experiment, int frame_width_px,
                                                           int frame_height_px, GlContextFactory gl_context);

// Whether `view` is all of `frame` (a mono display's eye).
inline bool covers_frame(const ImageRGBA& frame, const PixelRect& view) {
  return view.x_px == 0 && view.y_px == 0 && view.width_px == frame.width_px && view.height_px == frame.height_px;
}

// An eye's part of a whole frame: the frame itself where the eye's view is all of it (no copy),
// else the view cropped out of it (crop_view). Holds a reference to `frame`.
class ViewPart {
 public:
  ViewPart(const ImageRGBA& frame, const PixelRect& view)
      : cropped_(covers_frame(frame, view) ? std::nullopt : std::optional<ImageRGBA>(crop_view(frame, view))),
        image_(cropped_ ? static_cast<const ImageRGBA&>(*cropped_) : frame) {}
  ViewPart(const ViewPart&) = delete;
  ViewPart& operator=(const ViewPart&) = delete;
  const ImageRGBA& image() const { return image_; }

 private:
  std::optional<ImageRGBA> cropped_;
  const ImageRGBA& image_;
};

// Before anything is written: in a stereo experiment every scene must fit its column in an eye's
// half of the display with as many scenes side by side as a trial shows (sequential forced choice:
// one), and no condition may look through traced spectacles (the lens is traced about the
// display's centre, not an eye's view). Throws ConfigError at [display] stereo.
void check_stereo_layout(const Experiment& experiment, const SceneLibrary& scenes);

}  // namespace glarelab
