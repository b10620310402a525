#pragma once
// One interface for every way of showing frames. Window (GLFW) and offscreen (EGL, else OSMesa)
// are siblings behind it, created in one place (display_factory.cpp), where a backend is added
// without touching callers. Each backend owns a current OpenGL 4.5 core context and loads the GL
// entry points through its own get-proc-address (glad), so all of them live in one binary.
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/gl/gl_context.h"

namespace glarelab {

struct DisplayRequest {
  int width_px = 1280;
  int height_px = 720;
  double refresh_hz = 60.0;  // offscreen: the virtual refresh; window: what the monitor must run at
  int monitor = 0;           // window: index into the connected monitors
  bool fullscreen = false;
  bool vsync = true;
  bool visible = true;       // window: false for hidden test windows
  std::string title = "glarelab";
  int gl_major = 4;
  int gl_minor = 5;
  // Colour depth of the default framebuffer ([display] bits_per_channel): 8, 10 or 16 (half float);
  // 0 takes the backend's default. A window asks for it through GLFW hints and refuses to open
  // (DisplayError) when the achieved depth is lower; offscreen, the default framebuffer is float
  // (or 16-bit half float) and the depth is made by the frame renderer's quantising target
  // (stimuli/frame_renderer.h), so it is always met.
  int bits_per_channel = 0;
  std::vector<std::string> required_extensions;
};

// One input from the person at the display, in the order it happened.
struct InputEvent {
  // A key: "left", "right", "up", "down", "escape", "space", "enter", "backspace", "a".."z", "0".."9";
  // or one click of the mouse wheel: "wheel_up" (away from the user) or "wheel_down".
  std::string name;
  bool shift = false;  // Shift was held (the fine mode of the adjustment task)
  bool is_key() const { return !name.starts_with("wheel_"); }
};

// A display is also the GL context it draws with (core/gl/gl_context.h: gl_info, make_current).
class DisplayBackend : public GlContext {
 public:
  virtual std::string kind() const = 0;  // "window" | "offscreen" (EGL and OSMesa both, headless_display.h; gl_info().platform says which)
  virtual int width_px() const = 0;   // size of the default framebuffer
  virtual int height_px() const = 0;
  // The refresh rate frames are scheduled at (monitor's for a window, the requested for offscreen).
  virtual double refresh_hz() const = 0;
  // True when frames reach a real display and time must come from the monotonic clock.
  virtual bool real_time() const = 0;
  // Presents the default framebuffer: a vsync'd buffer swap for a window, glFinish offscreen.
  virtual void present() = 0;
  // True when the default framebuffer still holds what was drawn into it after present() (an
  // offscreen buffer; a window's back buffer is undefined after a swap): a frame drawn there once
  // need not be drawn again for the next flip.
  virtual bool keeps_presented_frame() const { return false; }
  // The framebuffer a frame is drawn into for present(): 0, the default framebuffer, for a window
  // and offscreen; the OpenXR display's own float frame (runner/display/openxr_display.h), whose
  // halves go to its views' swapchain images unrounded and which it shows in its mirror window.
  virtual unsigned frame_framebuffer() const { return 0; }
  // Keys pressed and wheel clicks since the last call, in order (window); none offscreen.
  virtual std::vector<InputEvent> poll_input() = 0;
  // The keys of poll_input(); wheel clicks are dropped (the wheel only adjusts, it never answers).
  std::vector<std::string> poll_keys() {
    std::vector<std::string> keys;
    for (const InputEvent& event : poll_input())
      if (event.is_key()) keys.push_back(event.name);
    return keys;
  }
  // The user closed the window (or, in a headset, its runtime ended the session).
  virtual bool close_requested() const = 0;
  // Why, in the words stored as the aborted session's reason.
  virtual std::string close_reason() const { return "window closed"; }
  // How the picture reaches the screen, for the session log (runner/display/display_info.h): a
  // window's monitor and its video mode, full screen or windowed; offscreen, the buffer's size.
  virtual std::string display_mode() const {
    return kind() + " " + std::to_string(width_px()) + "x" + std::to_string(height_px()) + ", no monitor";
  }
};

// The one place a backend is chosen: kind is "window", "offscreen" (EGL, else OSMesa), "egl" or
// "osmesa" (runner/display/display_factory.cpp).
std::unique_ptr<DisplayBackend> create_display(const std::string& kind, const DisplayRequest& request);
std::vector<std::string> display_kinds();

// Loads GL entry points with `get_proc` (glad), reads GlInfo, and checks the version and
// extensions; throws DisplayError naming what was required and what was found.
using GlProcLoader = void* (*)(const char* name);
GlInfo load_and_check_gl(const char* subsystem, GlProcLoader get_proc, const DisplayRequest& request);

// "; the driver offers OpenGL <version> on <renderer>" for the context current on this thread,
// asked through `get_proc` without loading the full entry-point table (used when a requested
// context was refused and a default one was created just to say what the driver offers).
std::string describe_offered_context(GlProcLoader get_proc);

// The backend whose context is current on this thread with its own entry points in glad's table,
// as far as glarelab made it so (nullptr: not known). Every way glarelab makes a context current
// says so here; the EGL backend, asked to make itself current while it still is, then skips the
// make-current and the table's reload (about 700 look-ups), which a GL engine frame asked for four
// to six times (docs/PERFORMANCE.md, the H200 of 30 November).
void note_current_gl_backend(const void* backend);
const void* current_gl_backend();

}  // namespace glarelab
