// The session side of a response-device unplug: the pause message on screen until the device is
// back or the session ends, and the re-run of the trial that the pause interrupted.
#include "runner/session/device_pause_screen.h"
#include "runner/session/session_loop.h"

namespace glarelab {

// --- response device (runner/session/response_device_input.h) ---
void SessionLoop::attach_response_device(ResponseDeviceInput* device, const ImageRGBA& pause_message) {
  device_ = device;
  pause_message_ = renderer_.upload(pause_message);
}

bool SessionLoop::take_trial_rerun() {
  if (!rerun_trial_) return false;
  rerun_trial_ = aborted_ = false;
  return true;
}

void SessionLoop::pause_for_response_device(int trial_index) {
  const auto show_frame = [&] {
    renderer_.compose({centred_placement(*pause_message_, display_.width_px(), display_.height_px())},
                      prepared_.experiment.display.background_cd_m2);
    encode();
    const double flip_s = present();
    timing_.on_flip(flip_s, trial_index, -1);
    after_flip(flip_s);
  };
  const auto message_pixels = [&] {
    return lit_pixels(renderer_.read_stimulus(), 0.5 * device_pause_text_cd_m2(prepared_.experiment.display));
  };
  const ResponseDeviceInput::PauseResult result = device_->pause(trial_index, display_, clock_, show_frame, message_pixels);
  aborted_ = true;
  if (result.resumed)
    rerun_trial_ = true;
  else
    abort_reason_ = result.abort_reason;
}
// --- end response device ---

}  // namespace glarelab
