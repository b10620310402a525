#include "glare/glare_backend.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "core/errors.h"
#include "glare/cpu/backend.h"
#include "glare/gl/backend.h"
#include "glare/wave/psf_scale.h"

namespace glarelab {

bool is_software_renderer(const std::string& gl_renderer) {
  std::string lower = gl_renderer;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* software : {"llvmpipe", "softpipe", "swrast", "svga3d"})
    if (lower.find(software) != std::string::npos) return true;
  return false;
}

GlareBackendChoice create_glare_backend(const std::string& name, const GlareBackendSettings& settings) {
  const auto cpu = [&] { return std::make_unique<CpuGlareBackend>(settings.cpu_precision); };
  if (name == "cpu") {
    auto backend = cpu();
    const std::string picked = backend->name();
    return {std::move(backend), "glare backend " + picked + ": asked for by name."};
  }
  const auto make_context = [&]() -> std::unique_ptr<GlContext> {
    if (!settings.gl_context) throw DisplayError("OpenGL: no context factory was given to the glare engine");
    return settings.gl_context();
  };
  if (name == "gl") {
    auto backend = std::make_unique<gl::GlGlareBackend>(make_context());
    const std::string renderer = backend->gl_info().renderer;
    return {std::move(backend), "glare backend gl: asked for by name (OpenGL renderer " + renderer + ")."};
  }
  if (name != "auto")
    throw std::invalid_argument("glare backend: unknown name '" + name + "' (expected cpu, gl or auto)");
  std::unique_ptr<GlContext> context;
  try {
    context = make_context();
  } catch (const DisplayError& error) {
    auto backend = cpu();
    const std::string picked = backend->name();
    return {std::move(backend), "glare backend auto picked " + picked + ": no OpenGL 4.5 context (" + error.what() + ")."};
  }
  const std::string renderer = context->gl_info().renderer;
  if (is_software_renderer(renderer)) {
    context.reset();
    auto backend = cpu();
    const std::string picked = backend->name();
    return {std::move(backend), "glare backend auto picked " + picked + ": the OpenGL renderer is " + renderer +
                                    ", a software rasteriser: the GL path would run on the same CPU cores, slower than FFTW "
                                    "(docs/PERFORMANCE.md)."};
  }
  return {std::make_unique<gl::GlGlareBackend>(std::move(context)),
          "glare backend auto picked gl: the OpenGL renderer " + renderer + " is a hardware GPU."};
}

ImageRGBA apply_glare(GlareBackend& backend, const ImageRGBA& image, double image_degrees_per_pixel,
                      const ApertureGeometry& geometry, const PsfOptions& options) {
  if (!geometry.glare_enabled) return image;  // control: no glare, the stimulus as it is
  const Psf psf = backend.psf(geometry, options);
  return backend.convolve(image, resample_psf_to_display(psf, image_degrees_per_pixel));
}

}  // namespace glarelab
