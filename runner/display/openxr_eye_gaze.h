#pragma once
// The headset's eye tracker as an OpenXR action (XR_EXT_eye_gaze_interaction; docs/STEREO.md, "Eye
// gaze"): a pose action bound to /interaction_profiles/ext/eye_gaze_interaction's
// /user/eyes_ext/input/gaze_ext/pose, in an action set of its own that the connection attaches and
// syncs with the answers' (runner/display/openxr_session.cpp), and its action space, located at each
// frame's predicted display time in the VIEW space and turned into a point on each eye's view image
// (runner/display/headset_gaze.h). Only built where CMake found the loader.
#include <openxr/openxr.h>

#include <string>

#include "runner/display/headset_gaze.h"
#include "runner/display/openxr_owner.h"

namespace glarelab {

class OpenXrEyeGaze {
 public:
  // Creates the set and the gaze action and suggests the eye gaze profile's binding. The instance
  // has XR_EXT_eye_gaze_interaction enabled and its system supports eye gaze interaction. Throws
  // DisplayError "OpenXR: ..." when the runtime refuses any of it.
  OpenXrEyeGaze(XrInstance instance, XrSession session);
  OpenXrEyeGaze(const OpenXrEyeGaze&) = delete;
  OpenXrEyeGaze& operator=(const OpenXrEyeGaze&) = delete;

  // The set, to attach and to sync.
  XrActionSet action_set() const { return set_.get(); }
  // Once the set is attached: the gaze action's space (its pose as the runtime gives it).
  void create_space();
  // The gaze at `time`, located in `view_space`, as a point on each of `views` (located in the same
  // space at the same time, left eye first); untracked where the runtime gives no valid orientation.
  HeadsetGazeSample locate(XrSpace view_space, XrTime time, const XrView views[2]) const;

 private:
  XrInstance instance_;
  XrSession session_;
  XrOwner<XrActionSet, xrDestroyActionSet> set_;
  XrOwner<XrAction, xrDestroyAction> gaze_;
  XrOwner<XrSpace, xrDestroySpace> space_;
};

}  // namespace glarelab
