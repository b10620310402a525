#pragma once
// Presses of a headset's controllers (the OpenXR display's answer actions, docs/STEREO.md
// "Controllers"), as the session takes them: which button, which answer position it stands for, and
// when the runtime saw it change. No OpenXR types here.
#include <chrono>
#include <string>
#include <vector>

namespace glarelab {

struct ControllerPress {
  // The action pressed, as logged: "left hand select", "right hand select", "menu".
  std::string button;
  // The answer it gives: the trial's allowed response at this position (1: the first, as the
  // digit key "1" does; runner/session/keyboard_responses.h).
  int answer_position = 0;
  // When the runtime saw the button go down (XrActionStateBoolean::lastChangeTime, on steady_clock,
  // CLOCK_MONOTONIC).
  std::chrono::steady_clock::time_point pressed;
};

// A display whose runtime has controllers (the OpenXR display): the presses since the last call,
// in the order the runtime saw them.
class ControllerPressSource {
 public:
  virtual ~ControllerPressSource() = default;
  virtual std::vector<ControllerPress> take_controller_presses() = 0;
};

}  // namespace glarelab
