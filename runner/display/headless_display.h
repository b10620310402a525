#pragma once
// What the two offscreen backends (egl_display.cpp, osmesa_display.cpp) share: a default
// framebuffer of the requested size, frames timed by the virtual clock, no input, and presenting
// as waiting for the GPU (glFinish). Each backend adds how its context is made and made current.
#include <string>
#include <vector>

#include "runner/display/display_backend.h"

namespace glarelab {

class HeadlessDisplay : public DisplayBackend {
 public:
  std::string kind() const override { return "offscreen"; }
  const GlInfo& gl_info() const override { return info_; }
  int width_px() const override { return width_px_; }
  int height_px() const override { return height_px_; }
  double refresh_hz() const override { return refresh_hz_; }
  bool real_time() const override { return false; }
  void present() override;
  bool keeps_presented_frame() const override { return true; }
  std::vector<InputEvent> poll_input() override { return {}; }
  bool close_requested() const override { return false; }

 protected:
  // Throws DisplayError "SUBSYSTEM: framebuffer size must be at least 1x1".
  HeadlessDisplay(const DisplayRequest& request, const std::string& subsystem);

  int width_px_;
  int height_px_;
  double refresh_hz_;
  GlInfo info_;  // set by the backend once its context is current
};

}  // namespace glarelab
