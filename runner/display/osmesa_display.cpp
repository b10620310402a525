#include "runner/display/osmesa_display.h"

// glad first: it blocks GL/gl.h, which osmesa.h would otherwise pull in.
#include <glad/gl.h>
#include <GL/osmesa.h>

#include <dlfcn.h>

#include <sstream>
#include <string>
#include <vector>

#include "runner/display/headless_display.h"

namespace glarelab {
namespace {

// libOSMesa is opened when an OSMesa display is first made, not linked: it pulls in libLLVM, whose
// loading cost every glarelab process about 0.1 s of CPU (relocations and page faults) at start,
// though most commands and most test processes never draw (docs/PERFORMANCE.md, "The test suite").
// The entry points are OSMesa's own API (GL/osmesa.h), looked up once.
struct OsMesaLibrary {
  decltype(&OSMesaCreateContextAttribs) create_context_attribs = nullptr;
  decltype(&OSMesaCreateContextExt) create_context_ext = nullptr;
  decltype(&OSMesaDestroyContext) destroy_context = nullptr;
  decltype(&OSMesaMakeCurrent) make_current = nullptr;
  decltype(&OSMesaPixelStore) pixel_store = nullptr;
  decltype(&OSMesaGetProcAddress) get_proc_address = nullptr;
};

template <typename Function>
void look_up(void* library, const char* name, Function& function) {
  function = reinterpret_cast<Function>(dlsym(library, name));
  if (function == nullptr) throw DisplayError(std::string("OSMesa: libOSMesa.so.8 has no ") + name);
}

const OsMesaLibrary& osmesa() {
  static const OsMesaLibrary library = [] {
    // Kept open for the process: contexts may live until exit.
    void* handle = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = dlerror();
      throw DisplayError(std::string("OSMesa: cannot load libOSMesa.so.8 (Debian package libosmesa6): ") +
                         (why != nullptr ? why : "unknown error"));
    }
    OsMesaLibrary found;
    look_up(handle, "OSMesaCreateContextAttribs", found.create_context_attribs);
    look_up(handle, "OSMesaCreateContextExt", found.create_context_ext);
    look_up(handle, "OSMesaDestroyContext", found.destroy_context);
    look_up(handle, "OSMesaMakeCurrent", found.make_current);
    look_up(handle, "OSMesaPixelStore", found.pixel_store);
    look_up(handle, "OSMesaGetProcAddress", found.get_proc_address);
    return found;
  }();
  return library;
}

void* osmesa_proc(const char* name) { return reinterpret_cast<void*>(osmesa().get_proc_address(name)); }

class OsMesaDisplay final : public HeadlessDisplay {
 public:
  OsMesaDisplay(const DisplayRequest& request, const std::string& why_not_egl)
      : HeadlessDisplay(request, "OSMesa") {
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              24,
                              OSMESA_STENCIL_BITS,
                              0,
                              OSMESA_ACCUM_BITS,
                              0,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              request.gl_major,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              request.gl_minor,
                              0};
    context_ = osmesa().create_context_attribs(attributes, nullptr);
    if (context_ == nullptr) {
      std::ostringstream message;
      message << "OSMesa: could not create an OpenGL " << request.gl_major << "." << request.gl_minor
              << " core context" << describe_fallback();
      throw DisplayError(message.str());
    }
    // A float colour buffer (as Filament's PlatformOSMesa): what is read back keeps the full
    // precision of the rendered stimulus, not 8 bits.
    buffer_.assign(static_cast<std::size_t>(width_px_) * static_cast<std::size_t>(height_px_) * 4, 0.0f);
    make_current();
    info_ = load_and_check_gl("OSMesa", osmesa_proc, request);
    loaded_ = true;
    info_.platform = why_not_egl.empty() ? "OSMesa" : "OSMesa (EGL did not start: " + why_not_egl + ")";
  }

  ~OsMesaDisplay() override {
    if (context_ != nullptr) osmesa().destroy_context(context_);
  }

  void make_current() override {
    note_current_gl_backend(nullptr);  // OSMesa switches Mesa's dispatch without EGL knowing
    if (!osmesa().make_current(context_, buffer_.data(), GL_FLOAT, width_px_, height_px_)) {
      throw DisplayError("OSMesa: OSMesaMakeCurrent failed for a float buffer of " + std::to_string(width_px_) + "x" +
                         std::to_string(height_px_));
    }
    // Rows in memory run top to bottom, like every image in glarelab.
    osmesa().pixel_store(OSMESA_Y_UP, 0);
    // Entry points may differ between contexts (an EGL or GLFW context's were loaded last).
    if (loaded_ && gladLoadGL(reinterpret_cast<GLADloadfunc>(osmesa_proc)) == 0)
      throw DisplayError("OSMesa: could not reload OpenGL entry points");
  }

 private:
  // When the requested version is refused, say what the driver does offer by creating a
  // default context just to ask it.
  static std::string describe_fallback() {
    OSMesaContext probe = osmesa().create_context_ext(OSMESA_RGBA, 0, 0, 0, nullptr);
    if (probe == nullptr) return " (and no default context could be created either)";
    std::vector<float> pixel(4);
    std::string found;
    note_current_gl_backend(nullptr);
    if (osmesa().make_current(probe, pixel.data(), GL_FLOAT, 1, 1)) found = describe_offered_context(osmesa_proc);
    osmesa().destroy_context(probe);
    return found;
  }

  OSMesaContext context_ = nullptr;
  std::vector<float> buffer_;
  bool loaded_ = false;  // entry points loaded once by load_and_check_gl
};

}  // namespace

std::unique_ptr<DisplayBackend> create_osmesa_display(const DisplayRequest& request, const std::string& why_not_egl) {
  return std::make_unique<OsMesaDisplay>(request, why_not_egl);
}

}  // namespace glarelab
