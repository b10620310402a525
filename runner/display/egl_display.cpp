#include "runner/display/egl_display.h"

#include "runner/display/gl_driver_pin.h"

// glad first: it blocks GL/gl.h, which the EGL headers would otherwise pull in.
#include <glad/gl.h>
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <mutex>
#include <sstream>
#include <vector>

#include "runner/display/headless_display.h"

namespace glarelab {
namespace {

void* egl_proc(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

std::string egl_error_name(EGLint code) {
  switch (code) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    default: {
      std::ostringstream text;
      text << "EGL error 0x" << std::hex << code;
      return text.str();
    }
  }
}

bool has_word(const char* list, const char* word) {
  if (list == nullptr) return false;
  const std::size_t length = std::strlen(word);
  for (const char* at = std::strstr(list, word); at != nullptr; at = std::strstr(at + 1, word))
    if ((at == list || at[-1] == ' ') && (at[length] == ' ' || at[length] == '\0')) return true;
  return false;
}

// An initialised EGLDisplay shared by every context of the process: eglGetPlatformDisplay returns
// the same handle for the same platform and device, and eglTerminate would end every context on
// it, so it is terminated once, when the last context made on it is gone.
struct EglConnection {
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string platform;  // "EGL device (hardware)", "EGL surfaceless", "EGL device (software)"
  ~EglConnection() {
    if (display != EGL_NO_DISPLAY) eglTerminate(display);
  }
};

std::shared_ptr<EglConnection> connect(std::string& tried) {
  static std::mutex mutex;
  static std::weak_ptr<EglConnection> shared;
  std::lock_guard lock(mutex);
  if (auto existing = shared.lock()) return existing;

  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (client_extensions == nullptr) {
    tried = "no EGL client extensions (libEGL without EGL 1.5 platforms)";
    return nullptr;
  }
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) {
    tried = "eglGetPlatformDisplayEXT missing";
    return nullptr;
  }
  const auto try_display = [&](EGLenum platform, void* native, const std::string& name) -> std::shared_ptr<EglConnection> {
    EGLDisplay display = get_platform_display(platform, native, nullptr);
    if (display == EGL_NO_DISPLAY) {
      tried += (tried.empty() ? "" : "; ") + name + ": no display (" + egl_error_name(eglGetError()) + ")";
      return nullptr;
    }
    if (eglInitialize(display, nullptr, nullptr) != EGL_TRUE) {
      tried += (tried.empty() ? "" : "; ") + name + ": eglInitialize failed (" + egl_error_name(eglGetError()) + ")";
      return nullptr;
    }
    keep_gl_driver_loaded();  // the vendor library and driver eglInitialize loaded stay mapped (gl_driver_pin.h)
    auto connection = std::make_shared<EglConnection>();
    connection->display = display;
    connection->platform = name;
    return connection;
  };

  std::shared_ptr<EglConnection> connection;
  std::vector<EGLDeviceEXT> software_devices;
  if (has_word(client_extensions, "EGL_EXT_platform_device") && has_word(client_extensions, "EGL_EXT_device_enumeration")) {
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_device_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLint count = 0;
    std::vector<EGLDeviceEXT> devices(16);
    if (query_devices != nullptr && query_devices(static_cast<EGLint>(devices.size()), devices.data(), &count) == EGL_TRUE) {
      devices.resize(static_cast<std::size_t>(count));
      for (EGLDeviceEXT device : devices) {
        const char* device_extensions = query_device_string != nullptr ? query_device_string(device, EGL_EXTENSIONS) : nullptr;
        if (has_word(device_extensions, "EGL_MESA_device_software")) {
          software_devices.push_back(device);
          continue;
        }
        if ((connection = try_display(EGL_PLATFORM_DEVICE_EXT, device, "EGL device (hardware)"))) break;
      }
      if (devices.empty()) tried += (tried.empty() ? "" : "; ") + std::string("EGL device: no devices");
    }
  }
  if (!connection && has_word(client_extensions, "EGL_MESA_platform_surfaceless"))
    connection = try_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, "EGL surfaceless");
  for (std::size_t i = 0; !connection && i < software_devices.size(); ++i)
    connection = try_display(EGL_PLATFORM_DEVICE_EXT, software_devices[i], "EGL device (software)");
  if (!connection && tried.empty())
    tried = "neither EGL_EXT_platform_device nor EGL_MESA_platform_surfaceless is offered";
  if (connection) shared = connection;
  return connection;
}

// "; the driver offers OpenGL ..." from a default context made only to ask (as the OSMesa and
// GLFW backends say when a version is refused), or nothing when none can be made either.
std::string describe_default_context(EGLDisplay display, EGLConfig config) {
  const EGLContext probe = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
  if (probe == EGL_NO_CONTEXT) return "";
  const EGLint size[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
  const EGLSurface surface = eglCreatePbufferSurface(display, config, size);
  std::string found;
  const EGLContext before = eglGetCurrentContext();
  const EGLSurface before_draw = eglGetCurrentSurface(EGL_DRAW), before_read = eglGetCurrentSurface(EGL_READ);
  if (surface != EGL_NO_SURFACE && eglMakeCurrent(display, surface, surface, probe) == EGL_TRUE) {
    note_current_gl_backend(nullptr);
    found = describe_offered_context(egl_proc);
    if (eglMakeCurrent(display, before_draw, before_read, before) != EGL_TRUE)
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  if (surface != EGL_NO_SURFACE) eglDestroySurface(display, surface);
  eglDestroyContext(display, probe);
  return found;
}

class EglDisplay final : public HeadlessDisplay {
 public:
  explicit EglDisplay(const DisplayRequest& request)
      : HeadlessDisplay(request, "EGL") {
    std::string tried;
    connection_ = connect(tried);
    if (!connection_) throw DisplayError("EGL: no display could be opened: " + tried);
    const EGLDisplay display = connection_->display;
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE)
      throw DisplayError("EGL: " + connection_->platform + " does not offer desktop OpenGL (eglBindAPI: " +
                         egl_error_name(eglGetError()) + ")");
    // A float pbuffer (EGL_EXT_pixel_format_float) keeps drive values finer than 8 bits, as
    // OSMesa's float buffer does; an 8-bit one where float is not offered.
    const bool float_pixels = has_word(eglQueryString(display, EGL_EXTENSIONS), "EGL_EXT_pixel_format_float");
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (float_pixels) {
      const EGLint float_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                         EGL_COLOR_COMPONENT_TYPE_EXT, EGL_COLOR_COMPONENT_TYPE_FLOAT_EXT,
                                         EGL_RED_SIZE, 16, EGL_GREEN_SIZE, 16, EGL_BLUE_SIZE, 16, EGL_ALPHA_SIZE, 16,
                                         EGL_NONE};
      eglChooseConfig(display, float_attributes, &config, 1, &configs);
    }
    if (configs < 1) {
      const EGLint attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                   EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8, EGL_NONE};
      if (eglChooseConfig(display, attributes, &config, 1, &configs) != EGL_TRUE || configs < 1)
        throw DisplayError("EGL: " + connection_->platform + " offers no OpenGL pbuffer configuration");
      pixel_format_ = "RGBA8";
    }
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, request.gl_major,
                                         EGL_CONTEXT_MINOR_VERSION, request.gl_minor,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_NONE};
    context_ = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
    if (context_ == EGL_NO_CONTEXT) {
      std::ostringstream message;
      message << "EGL: " << connection_->platform << ": could not create an OpenGL " << request.gl_major << "."
              << request.gl_minor << " core context (" << egl_error_name(eglGetError()) << ")"
              << describe_default_context(display, config);
      throw DisplayError(message.str());
    }
    const EGLint surface_attributes[] = {EGL_WIDTH, width_px_, EGL_HEIGHT, height_px_, EGL_NONE};
    surface_ = eglCreatePbufferSurface(display, config, surface_attributes);
    if (surface_ == EGL_NO_SURFACE) {
      const std::string error = egl_error_name(eglGetError());
      eglDestroyContext(display, context_);
      throw DisplayError("EGL: " + connection_->platform + ": could not create a " + std::to_string(width_px_) + "x" +
                         std::to_string(height_px_) + " pbuffer (" + error + ")");
    }
    make_current();
    info_ = load_and_check_gl("EGL", egl_proc, request);
    note_current_gl_backend(this);
    info_.platform = connection_->platform + ", " + pixel_format_ + " pbuffer";
  }

  ~EglDisplay() override {
    const EGLDisplay display = connection_->display;
    if (current_gl_backend() == this) note_current_gl_backend(nullptr);
    if (eglGetCurrentContext() == context_) eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroySurface(display, surface_);
    eglDestroyContext(display, context_);
  }

  void make_current() override {
    // Still current, as EGL says and as glarelab last made it, with this context's entry points.
    if (current_gl_backend() == this && eglGetCurrentContext() == context_ &&
        eglGetCurrentSurface(EGL_DRAW) == surface_)
      return;
    note_current_gl_backend(nullptr);
    if (eglMakeCurrent(connection_->display, surface_, surface_, context_) != EGL_TRUE)
      throw DisplayError("EGL: eglMakeCurrent failed (" + egl_error_name(eglGetError()) + ")");
    // Entry points may differ between contexts (another backend's were loaded last).
    if (gladLoadGL(reinterpret_cast<GLADloadfunc>(egl_proc)) == 0)
      throw DisplayError("EGL: could not reload OpenGL entry points");
    note_current_gl_backend(this);
  }

 private:
  std::shared_ptr<EglConnection> connection_;
  EGLContext context_ = EGL_NO_CONTEXT;
  EGLSurface surface_ = EGL_NO_SURFACE;
  std::string pixel_format_ = "RGBA16F";
};

}  // namespace

std::unique_ptr<DisplayBackend> create_egl_display(const DisplayRequest& request) {
  return std::make_unique<EglDisplay>(request);
}

}  // namespace glarelab
