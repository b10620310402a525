#include "runner/display/glfw_display.h"

#include "runner/display/gl_driver_pin.h"

#include <glad/gl.h>
// GLFW after glad: glad provides the GL declarations, GLFW must not include system GL headers.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <sstream>
#include <string>

namespace glarelab {
namespace {


// GLFW reports errors through a callback; keep the last one so exceptions can quote it.
std::string& last_glfw_error() {
  static std::string message;
  return message;
}
void record_glfw_error(int code, const char* description) {
  std::ostringstream text;
  text << (description ? description : "unknown error") << " (GLFW error 0x" << std::hex << code << ")";
  last_glfw_error() = text.str();
}

// glfwInit/glfwTerminate are process-wide; count the windows that need the library.
std::mutex glfw_mutex;
int glfw_users = 0;

void acquire_glfw() {
  std::lock_guard lock(glfw_mutex);
  if (glfw_users == 0) {
    glfwSetErrorCallback(record_glfw_error);
    last_glfw_error().clear();
    if (glfwInit() != GLFW_TRUE) {
      const char* display = std::getenv("DISPLAY");
      std::string message = "GLFW: cannot open a window: " + last_glfw_error();
      message += display && *display ? std::string(" (DISPLAY=") + display + ")" : " (DISPLAY is not set)";
      message += ". On a machine without a display use --display offscreen.";
      throw DisplayError(message);
    }
  }
  ++glfw_users;
}

void release_glfw() {
  std::lock_guard lock(glfw_mutex);
  if (--glfw_users == 0) glfwTerminate();
}

void* glfw_proc(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

std::string key_name(int key) {
  switch (key) {
    case GLFW_KEY_LEFT: return "left";
    case GLFW_KEY_RIGHT: return "right";
    case GLFW_KEY_UP: return "up";
    case GLFW_KEY_DOWN: return "down";
    case GLFW_KEY_ESCAPE: return "escape";
    case GLFW_KEY_SPACE: return "space";
    case GLFW_KEY_BACKSPACE: return "backspace";
    case GLFW_KEY_ENTER:
    case GLFW_KEY_KP_ENTER: return "enter";
    default: break;
  }
  if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) return std::string(1, static_cast<char>('a' + (key - GLFW_KEY_A)));
  if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) return std::string(1, static_cast<char>('0' + (key - GLFW_KEY_0)));
  if (key >= GLFW_KEY_KP_0 && key <= GLFW_KEY_KP_9) return std::string(1, static_cast<char>('0' + (key - GLFW_KEY_KP_0)));
  return {};
}

class GlfwDisplay final : public DisplayBackend {
 public:
  explicit GlfwDisplay(const DisplayRequest& request) {
    acquire_glfw();
    try {
      open(request);
    } catch (...) {
      if (window_ != nullptr) glfwDestroyWindow(window_);
      release_glfw();
      throw;
    }
  }

  ~GlfwDisplay() override {
    glfwDestroyWindow(window_);
    release_glfw();
  }

  std::string kind() const override { return "window"; }
  const GlInfo& gl_info() const override { return info_; }
  int width_px() const override { return width_px_; }
  int height_px() const override { return height_px_; }
  double refresh_hz() const override { return refresh_hz_; }
  bool real_time() const override { return true; }
  void present() override { glfwSwapBuffers(window_); }
  bool close_requested() const override { return glfwWindowShouldClose(window_) == GLFW_TRUE; }
  std::string display_mode() const override { return display_mode_; }
  void make_current() override {
    // Release first: another context on this thread (the OSMesa context of the GL glare path, or
    // the one "auto" opens to look at the renderer) switches Mesa's shared GL dispatch without GLX
    // knowing, and GLX (glvnd) skips a make-current to the context it believes is still current,
    // which left the dispatch empty ("could not reload OpenGL entry points").
    note_current_gl_backend(nullptr);
    glfwMakeContextCurrent(nullptr);
    glfwMakeContextCurrent(window_);
    if (gladLoadGL(reinterpret_cast<GLADloadfunc>(glfw_proc)) == 0)
      throw DisplayError("GLFW: could not reload OpenGL entry points");
  }

  std::vector<InputEvent> poll_input() override {
    glfwPollEvents();
    std::vector<InputEvent> input;
    input.swap(pending_input_);
    return input;
  }

 private:
  void open(const DisplayRequest& request) {
    int monitor_count = 0;
    GLFWmonitor** monitors = glfwGetMonitors(&monitor_count);
    if (monitor_count == 0) throw DisplayError("GLFW: no monitor is connected (" + last_glfw_error() + ")");
    if (request.monitor < 0 || request.monitor >= monitor_count) {
      throw DisplayError("GLFW: monitor " + std::to_string(request.monitor) + " requested, but " +
                         std::to_string(monitor_count) + " monitor(s) are connected (indices 0.." +
                         std::to_string(monitor_count - 1) + ")");
    }
    GLFWmonitor* monitor = monitors[request.monitor];
    const GLFWvidmode* mode = glfwGetVideoMode(monitor);

    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, request.gl_major);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, request.gl_minor);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    glfwWindowHint(GLFW_VISIBLE, request.visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
    // Display encoding is applied by our own shader (sRGB or a configured gamma), so the window's
    // framebuffer must not re-encode.
    glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE);
    // The colour depth [display] bits_per_channel asks for (10: a 10-bit panel path, 30-bit
    // visual; 16: a half-float framebuffer where the platform offers one). Hints are requests:
    // the depth achieved is checked after creation.
    if (request.bits_per_channel != 0) {
      const int alpha_bits = request.bits_per_channel == 10 ? 2 : request.bits_per_channel;
      glfwWindowHint(GLFW_RED_BITS, request.bits_per_channel);
      glfwWindowHint(GLFW_GREEN_BITS, request.bits_per_channel);
      glfwWindowHint(GLFW_BLUE_BITS, request.bits_per_channel);
      glfwWindowHint(GLFW_ALPHA_BITS, alpha_bits);
    }
    if (request.fullscreen && mode != nullptr) glfwWindowHint(GLFW_REFRESH_RATE, mode->refreshRate);

    last_glfw_error().clear();
    window_ = glfwCreateWindow(request.width_px, request.height_px, request.title.c_str(),
                               request.fullscreen ? monitor : nullptr, nullptr);
    if (window_ == nullptr) {
      std::ostringstream message;
      message << "GLFW: could not create an OpenGL " << request.gl_major << "." << request.gl_minor
              << " core window: " << last_glfw_error() << probe_default_context();
      throw DisplayError(message.str());
    }
    keep_gl_driver_loaded();
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, [](GLFWwindow* window, int key, int, int action, int mods) {
      if (action != GLFW_PRESS) return;
      auto* self = static_cast<GlfwDisplay*>(glfwGetWindowUserPointer(window));
      const std::string name = key_name(key);
      if (!name.empty()) self->pending_input_.push_back({name, (mods & GLFW_MOD_SHIFT) != 0});
    });
    // The wheel: a notched wheel reports +-1 per click; a touchpad reports fractions, which add up
    // to clicks. The scroll callback carries no modifiers, so Shift is read from the key state.
    glfwSetScrollCallback(window_, [](GLFWwindow* window, double, double y_offset) {
      auto* self = static_cast<GlfwDisplay*>(glfwGetWindowUserPointer(window));
      const bool shift = glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                         glfwGetKey(window, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
      self->wheel_clicks_ += y_offset;
      for (; self->wheel_clicks_ >= 1.0; self->wheel_clicks_ -= 1.0) self->pending_input_.push_back({"wheel_up", shift});
      for (; self->wheel_clicks_ <= -1.0; self->wheel_clicks_ += 1.0) self->pending_input_.push_back({"wheel_down", shift});
    });
    note_current_gl_backend(nullptr);
    glfwMakeContextCurrent(window_);
    // Vsync: one buffer swap per vertical refresh, so a stimulus of n frames stays n refreshes.
    glfwSwapInterval(request.vsync ? 1 : 0);
    glfwGetFramebufferSize(window_, &width_px_, &height_px_);
    refresh_hz_ = (mode != nullptr && mode->refreshRate > 0) ? mode->refreshRate : request.refresh_hz;
    display_mode_ = describe_mode(request, monitor, mode);
    info_ = load_and_check_gl("GLFW", glfw_proc, request);
    check_colour_depth(request);
  }

  // Reads the depth the default framebuffer got, logs it in the context's platform text (which
  // every session log records) and refuses a window shallower than requested: a 10-bit
  // experiment shown on 8 bits would lose the steps it was designed around.
  void check_colour_depth(const DisplayRequest& request) {
    GLint bits[3] = {0, 0, 0};
    GLint component_type = GL_UNSIGNED_NORMALIZED;
    const GLenum channels[3] = {GL_FRAMEBUFFER_ATTACHMENT_RED_SIZE, GL_FRAMEBUFFER_ATTACHMENT_GREEN_SIZE,
                                GL_FRAMEBUFFER_ATTACHMENT_BLUE_SIZE};
    for (int c = 0; c < 3; ++c) glGetNamedFramebufferAttachmentParameteriv(0, GL_BACK_LEFT, channels[c], &bits[c]);
    glGetNamedFramebufferAttachmentParameteriv(0, GL_BACK_LEFT, GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE, &component_type);
    const bool is_float = component_type == GL_FLOAT;
    std::ostringstream depth;
    depth << bits[0] << "/" << bits[1] << "/" << bits[2] << (is_float ? " float" : "") << " bits";
    info_.platform = "GLFW window, " + depth.str() + " framebuffer";
    const int wanted = request.bits_per_channel;
    if (wanted == 0) return;
    const int achieved = std::min({bits[0], bits[1], bits[2]});
    if (achieved < wanted || (wanted == 16 && !is_float))
      throw DisplayError("GLFW: [display] bits_per_channel = " + std::to_string(wanted) +
                         (wanted == 16 ? " (half float)" : "") + " requested, but the window's framebuffer has " +
                         depth.str() + " per channel (the driver, the monitor link or the desktop's colour depth "
                         "does not offer it)");
  }

  // "full screen on monitor 0 'DP-1': video mode 1920x1080 at 60 Hz, 8/8/8 bits" or "windowed
  // 1280x720 on monitor 0 ...": what the session log records as the display mode.
  std::string describe_mode(const DisplayRequest& request, GLFWmonitor* monitor, const GLFWvidmode* mode) const {
    std::ostringstream text;
    if (request.fullscreen)
      text << "full screen";
    else
      text << "windowed " << width_px_ << "x" << height_px_;
    const char* name = glfwGetMonitorName(monitor);
    text << " on monitor " << request.monitor << " '" << (name != nullptr ? name : "?") << "'";
    if (mode != nullptr)
      text << ": video mode " << mode->width << "x" << mode->height << " at " << mode->refreshRate << " Hz, "
           << mode->redBits << "/" << mode->greenBits << "/" << mode->blueBits << " bits";
    text << ", vsync " << (request.vsync ? "on" : "off");
    // A virtual X server (Xvfb) reports no rate: frames are then timed at the one asked for.
    if (mode == nullptr || mode->refreshRate <= 0)
      text << "; the monitor reports no refresh rate: timed at the requested " << request.refresh_hz << " Hz";
    return text.str();
  }

  // Names the OpenGL version the driver does offer when the requested one was refused.
  static std::string probe_default_context() {
    const std::string refusal = last_glfw_error();
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    GLFWwindow* probe = glfwCreateWindow(16, 16, "probe", nullptr, nullptr);
    if (probe == nullptr) return "";
    note_current_gl_backend(nullptr);
    glfwMakeContextCurrent(probe);
    const std::string found = describe_offered_context(glfw_proc);
    glfwMakeContextCurrent(nullptr);
    glfwDestroyWindow(probe);
    last_glfw_error() = refusal;
    return found;
  }

  GLFWwindow* window_ = nullptr;
  int width_px_ = 0;
  int height_px_ = 0;
  double refresh_hz_ = 60.0;
  GlInfo info_;
  std::string display_mode_;
  std::vector<InputEvent> pending_input_;
  double wheel_clicks_ = 0.0;  // scroll not yet a whole click
};

}  // namespace

std::unique_ptr<DisplayBackend> create_glfw_display(const DisplayRequest& request) {
  return std::make_unique<GlfwDisplay>(request);
}

}  // namespace glarelab
