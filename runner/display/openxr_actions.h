#pragma once
// The answer keys of a headset's controllers as an OpenXR action set (docs/STEREO.md,
// "Controllers"): three boolean actions standing for the trial's first, second and third allowed
// response, with suggested bindings for the common controllers' profiles; the connection attaches
// the set to the session and syncs it at each frame (runner/display/openxr_session.cpp), then the
// presses are read. Only built where CMake found the loader.
#include <openxr/openxr.h>

#include <string>
#include <vector>

#include "runner/display/openxr_owner.h"

namespace glarelab {

class OpenXrAnswerActions {
 public:
  // A press as the runtime reported it: the action and when its state went to true.
  struct Press {
    std::string button;
    int answer_position = 0;
    XrTime time = 0;
  };

  // Creates the set and its actions and suggests each profile's bindings (a profile the runtime
  // does not know is left out and named in describe()). Throws DisplayError "OpenXR: ..." when the
  // runtime refuses the set or takes no profile at all.
  OpenXrAnswerActions(XrInstance instance, XrSession session);
  OpenXrAnswerActions(const OpenXrAnswerActions&) = delete;
  OpenXrAnswerActions& operator=(const OpenXrAnswerActions&) = delete;

  // The set, to attach and to sync.
  XrActionSet action_set() const { return set_.get(); }
  // After an xrSyncActions of a focused session (not XR_SESSION_NOT_FOCUSED, when the runtime
  // reports every action inactive): each action whose state changed to pressed since the last sync
  // is appended to `presses`.
  void read(std::vector<Press>& presses);

  // "answer actions bound for khr/simple_controller, valve/index_controller, ..." for the display event.
  std::string describe() const;

 private:
  struct Answer {
    XrOwner<XrAction, xrDestroyAction> action;
    std::string button;
    int answer_position = 0;
  };
  XrInstance instance_;
  XrSession session_;
  XrOwner<XrActionSet, xrDestroyActionSet> set_;
  std::vector<Answer> answers_;
  std::vector<std::string> bound_profiles_;
  std::vector<std::string> refused_profiles_;
};

}  // namespace glarelab
