#pragma once
// The OpenXR side of the OpenXR display (runner/display/openxr_display.cpp): instance, system,
// session, reference spaces and one swapchain per view, each an RAII owner; the runtime's session
// states; and one frame of the runtime's loop (runner/display/openxr_frame.cpp). Only built where
// CMake found the loader.
#include <openxr/openxr.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "runner/display/controller_presses.h"
#include "runner/display/module_pin.h"
#include "runner/display/openxr_actions.h"
#include "runner/display/openxr_clock.h"
#include "runner/display/openxr_eye_gaze.h"

namespace glarelab {

class OpenXrConnection {
 public:
  // Creates the instance (XR_KHR_opengl_enable, XR_KHR_convert_timespec_time), finds a head-mounted
  // display with a PRIMARY_STEREO view configuration and checks that each view can be
  // view_width_px x view_height_px. Throws DisplayError "OpenXR: ..." (no runtime: with the loader's
  // own message).
  OpenXrConnection(int view_width_px, int view_height_px);
  ~OpenXrConnection();
  OpenXrConnection(const OpenXrConnection&) = delete;
  OpenXrConnection& operator=(const OpenXrConnection&) = delete;

  // The runtime's OpenGL requirement against the context's version.
  void check_gl_version(int major, int minor);
  // The session on the GLX context current on this thread, its spaces and swapchains.
  void open_session_on_current_glx_context();
  // Waits for READY (up to 10 s), begins the session and runs empty frames until the runtime's
  // frame timing has settled; returns its refresh rate (Hz), one over the display period. The
  // views are located at the last of those frames (fields_of_view()).
  double begin();
  // Each view's field of view (left eye first), as located when the session began.
  const std::vector<ViewFieldOfView>& fields_of_view() const { return fields_of_view_; }

  // Drains the runtime's events and follows its session states: READY begins the session,
  // STOPPING ends it, LOSS_PENDING and EXITING (and instance loss) end it for good.
  void poll_events();
  bool running() const { return running_; }
  // Asks the runtime to end the session (xrRequestExitSession): it then goes through STOPPING,
  // which ends it as any end by the runtime does; `why` is named in ended_reason().
  void request_exit(const std::string& why);
  // The runtime ended the session (ended_reason() says how); the display asks to close.
  bool ended() const { return !ended_reason_.empty(); }
  const std::string& ended_reason() const { return ended_reason_; }

  // One frame: xrWaitFrame, xrBeginFrame, xrLocateViews; for each view its swapchain image is
  // acquired, handed to draw_view(view, GL texture, GL internal format) and released; xrEndFrame
  // with a projection layer in the VIEW space (head-locked: each eye sees its half where the frame
  // put it). Returns the frame's predicted display time on steady_clock (CLOCK_MONOTONIC) and the
  // head's pose then (in the LOCAL space).
  using DrawView = std::function<void(int view, std::uint32_t gl_texture, std::int64_t gl_format)>;
  HeadPoseSample submit_frame(const DrawView& draw_view);

  // The controllers' presses (the answer action set, runner/display/openxr_actions.h, read at each
  // submitted frame) since the last call, their times on steady_clock.
  std::vector<ControllerPress> take_controller_presses();

  // The system's eye tracker (XR_EXT_eye_gaze_interaction, runner/display/openxr_eye_gaze.h): where
  // it has one, while keep_eye_gaze(true), each submitted frame of a focused session locates the
  // gaze at its predicted display time (runner/display/headset_gaze.h).
  bool has_eye_gaze() const { return eye_gaze_ != nullptr; }
  void keep_eye_gaze(bool keep);
  std::vector<HeadsetGazeSample> take_eye_gaze();
  const std::string& system_name() const { return system_name_; }

  // "runtime 'Monado(XRT) by Collabora et al ...' system 'Monado: Simulated HMD', 2 views 512x256
  // (recommended 320x240) in GL_RGBA16F, display period 50 ms, fields of view ...; answers from the
  // controllers ... bound for ...; eye gaze: ..." (the eye tracker, or why there is none)
  std::string describe() const;

 private:
  struct View {
    XrOwner<XrSwapchain, xrDestroySwapchain> swapchain;
    std::vector<std::uint32_t> gl_textures;
  };
  void on_state(XrSessionState state);
  // xrSyncActions of the answers' set and the eye gaze's; false when the session is not focused.
  bool sync_actions();
  void locate_fields_of_view(XrTime time);
  std::chrono::steady_clock::time_point to_steady(XrTime time) const;

  XrOwner<XrInstance, xrDestroyInstance> instance_;
  XrSystemId system_ = XR_NULL_SYSTEM_ID;
  XrOwner<XrSession, xrDestroySession> session_;
  XrOwner<XrSpace, xrDestroySpace> view_space_;
  XrOwner<XrSpace, xrDestroySpace> local_space_;
  std::vector<View> views_;
  std::vector<ViewFieldOfView> fields_of_view_;
  int view_width_px_;
  int view_height_px_;
  std::uint32_t recommended_width_px_ = 0;
  std::uint32_t recommended_height_px_ = 0;
  std::int64_t format_ = 0;
  std::string runtime_name_;
  std::string system_name_;
  XrDuration period_ns_ = 0;
  XrSessionState state_ = XR_SESSION_STATE_UNKNOWN;
  bool running_ = false;
  std::string ended_reason_;
  std::string exit_requested_;  // why request_exit() asked, empty when it did not
  std::unique_ptr<OpenXrAnswerActions> answers_;
  std::vector<OpenXrAnswerActions::Press> presses_;  // since take_controller_presses()
  bool eye_gaze_offered_ = false;    // the runtime offers XR_EXT_eye_gaze_interaction (enabled then)
  bool eye_gaze_supported_ = false;  // and the system has eye gaze
  std::unique_ptr<OpenXrEyeGaze> eye_gaze_;  // where the system has eye gaze
  bool keeping_eye_gaze_ = false;
  std::vector<HeadsetGazeSample> eye_gaze_samples_;  // since take_eye_gaze(), while keeping
  // Made before the runtime is first loaded and destroyed before every handle above: the runtime,
  // its API layers and the drivers they loaded stay mapped after xrDestroyInstance unloads them
  // (runner/display/module_pin.h).
  ModulesLoadedMeanwhileKept runtime_modules_kept_;
};

}  // namespace glarelab
