#include "runner/display/osmesa_display.h"

// glad first: it blocks GL/gl.h, which osmesa.h would otherwise pull in.
#include <glad/gl.h>
#include <GL/osmesa.h>

#include <sstream>
#include <vector>

#include "runner/display/headless_display.h"

namespace glarelab {
namespace {

void* osmesa_proc(const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }

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
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
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
    if (context_ != nullptr) OSMesaDestroyContext(context_);
  }

  void make_current() override {
    if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_FLOAT, width_px_, height_px_)) {
      throw DisplayError("OSMesa: OSMesaMakeCurrent failed for a float buffer of " + std::to_string(width_px_) + "x" +
                         std::to_string(height_px_));
    }
    // Rows in memory run top to bottom, like every image in glarelab.
    OSMesaPixelStore(OSMESA_Y_UP, 0);
    // Entry points may differ between contexts (an EGL or GLFW context's were loaded last).
    if (loaded_ && gladLoadGL(reinterpret_cast<GLADloadfunc>(osmesa_proc)) == 0)
      throw DisplayError("OSMesa: could not reload OpenGL entry points");
  }

 private:
  // When the requested version is refused, say what the driver does offer by creating a
  // default context just to ask it.
  static std::string describe_fallback() {
    OSMesaContext probe = OSMesaCreateContextExt(OSMESA_RGBA, 0, 0, 0, nullptr);
    if (probe == nullptr) return " (and no default context could be created either)";
    std::vector<float> pixel(4);
    std::string found;
    if (OSMesaMakeCurrent(probe, pixel.data(), GL_FLOAT, 1, 1)) found = describe_offered_context(osmesa_proc);
    OSMesaDestroyContext(probe);
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
