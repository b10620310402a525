#include "glare/glare_backend.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "core/errors.h"
#include "core/parallel_for.h"
#include "glare/cpu/float_glare.h"
#include "glare/cpu/backend.h"
#include "glare/cpu/fftw_wisdom.h"
#include "glare/gl/fft.h"
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

bool takes_chromatic_psf(const ApertureGeometry& geometry, const PsfOptions& options) {
  const DioptricPower& e = geometry.refraction_error;
  return options.spectral && (options.observer_refraction || e.xx() != 0.0 || e.xy() != 0.0 || e.yy() != 0.0);
}

std::vector<PixelRect> boxes_reached(const std::vector<PixelRect>& boxes, int psf_size_px, int width_px,
                                     int height_px) {
  const int reach = psf_size_px / 2;
  const PixelRect frame{0, 0, width_px, height_px};
  std::vector<PixelRect> reached;
  for (const PixelRect& box : boxes)
    reached.push_back(intersection(
        PixelRect{box.x_px - reach, box.y_px - reach, box.width_px + 2 * reach, box.height_px + 2 * reach}, frame));
  return reached;
}

Psf GlareBackend::display_psf(const ApertureGeometry& geometry, const PsfOptions& options,
                              double display_degrees_per_pixel) {
  return resample_psf_to_display(psf(geometry, options), display_degrees_per_pixel);
}

void GlareBackend::convolve_regions(const ImageRGBA& frame, const std::vector<PixelRect>& boxes,
                                    const Psf& display_psf, ImageRGBA& out) {
  const std::vector<PixelRect> reached = boxes_reached(boxes, display_psf.size_px, frame.width_px, frame.height_px);
  for (const PixelRect& area : reached) {
    if (reached.size() == 1 && area == image_rect(frame) && frame.depth.empty()) {
      out = convolve(frame, display_psf);  // the whole frame: no crop to copy
      return;
    }
    ImageRGBA part = crop(frame, area);
    part.depth.clear();  // convolve() takes colour only; out keeps the frame's depth
    paste(out, convolve(part, display_psf), area);
  }
}

void GlareBackend::convolve_regions_finished(const ImageRGBA& frame, const std::vector<PixelRect>& boxes,
                                             const Psf& display_psf, ImageRGBA& out, const RowFinish& finish,
                                             std::uint64_t, const ImageRGBA* added_to) {
  if (added_to != nullptr && (added_to->width_px != frame.width_px || added_to->height_px != frame.height_px))
    throw std::invalid_argument("glare backend: the image the glare is added to is not the frame's size");
  ImageRGBA convolved = frame;
  convolve_regions(frame, boxes, display_psf, convolved);
  if (added_to == nullptr) {
    out = std::move(convolved);
  } else {
    out = *added_to;
    for (std::size_t i = 0; i < out.rgba.size(); i += 4)
      for (std::size_t c = 0; c < 3; ++c) out.rgba[i + c] += convolved.rgba[i + c];
  }
  parallel_chunks(out.height_px, kGlareCpuThreads, [&](int first, int last) {
    for (int y = first; y < last; ++y) finish(y, 0, out.width_px, out.pixel(0, y));
  });
}

namespace {

// What checking a candidate found, kept for making it: the GL context made to read its renderer.
struct Probe {
  std::unique_ptr<GlContext> context;
  std::string renderer;
};

std::unique_ptr<GlContext> make_context(const GlareBackendSettings& settings) {
  if (!settings.gl_context) throw DisplayError("OpenGL: no context factory was given to the glare engine");
  return settings.gl_context();
}

// One row of the table (after GLFW's supportedPlatforms, src/platform.c): the request it answers
// besides "auto", whether it serves this use at all, why it cannot run here (for "auto"; nothing
// when it can), how it is made, and why it was taken.
struct Candidate {
  GlareBackendKind kind;
  GlareBackendRequest answers;
  bool (*serves)(const GlareBackendSettings&);
  std::optional<std::string> (*unavailable)(const GlareBackendSettings&, Probe&);
  std::unique_ptr<GlareBackend> (*make)(const GlareBackendSettings&, Probe&);
  // The clause after "glare backend [auto picked] KIND: ", when nothing before it was refused.
  std::string (*taken)(const GlareBackendSettings&, const Probe&, bool automatic);
  // A sentence after the reason (empty: none).
  std::string (*note)();
};

std::optional<std::string> gl_unavailable(const GlareBackendSettings& settings, Probe& probe) {
  if (settings.grid_px != 0 && !gl::is_power_of_two_fft_length(settings.grid_px))
    return "grid_px " + std::to_string(settings.grid_px) + " is not a power of two from 16 to 4096, which the GL path needs";
  try {
    probe.context = make_context(settings);
  } catch (const DisplayError& error) {
    return std::string("no OpenGL 4.5 context (") + error.what() + ")";
  }
  probe.renderer = probe.context->gl_info().renderer;
  if (!is_software_renderer(probe.renderer)) return std::nullopt;
  probe.context.reset();
  return "the OpenGL renderer is " + probe.renderer +
         ", a software rasteriser: the GL path would run on the same CPU cores, slower than FFTW (docs/PERFORMANCE.md)";
}

std::unique_ptr<GlareBackend> make_gl(const GlareBackendSettings& settings, Probe& probe) {
  auto backend = std::make_unique<gl::GlGlareBackend>(probe.context ? std::move(probe.context) : make_context(settings));
  probe.renderer = backend->gl_info().renderer;
  return backend;
}

std::string gl_taken(const GlareBackendSettings&, const Probe& probe, bool automatic) {
  return automatic ? "the OpenGL renderer " + probe.renderer + " is a hardware GPU"
                   : "asked for by name (OpenGL renderer " + probe.renderer + ")";
}

std::unique_ptr<GlareBackend> make_planned(const GlareBackendSettings& settings, Probe&) {
  const PsfOptions& psf = settings.frames->psf;
  CpuFloatGlareSettings planned;
  planned.grid_px = psf.grid_px;
  planned.aperture_width_mm = psf.aperture_width_mm;
  planned.supersampling = psf.supersampling;
  planned.reference_wavelength_nm = psf.wavelength_nm;
  planned.wavelength_samples = psf.wavelength_samples;
  planned.display_degrees_per_pixel = settings.frames->display_degrees_per_pixel;
  return std::make_unique<CpuFloatGlare>(planned);
}

std::string planned_note() {
  return "Planned: " + fftw_wisdom_place().describe() +
         ", a trial's frame spectrum kept; frame error against the float64 reference (backend = \"cpu\") about 2e-7 "
         "relative L2 at 32 wavelengths, 4e-6 at 16 (tests/glare_stage_test.cpp).";
}

std::unique_ptr<GlareBackend> make_cpu(const GlareBackendSettings& settings, Probe&) {
  return std::make_unique<CpuGlareBackend>(settings.cpu_precision);
}

std::string cpu_taken(const GlareBackendSettings& settings, const Probe&, bool) {
  return settings.named ? "asked for by name" : "the default (no backend named)";
}

std::optional<std::string> always_available(const GlareBackendSettings&, Probe&) { return std::nullopt; }
std::string no_note() { return {}; }

// In the order "auto" tries them.
constexpr Candidate kCandidates[] = {
    {GlareBackendKind::gl, GlareBackendRequest::gl, [](const GlareBackendSettings&) { return true; }, gl_unavailable,
     make_gl, gl_taken, no_note},
    // Only "auto" reaches it, and only for frames (a session's, `psf`'s) of the defocus phase, the
    // one its plans take.
    {GlareBackendKind::cpu_float32_planned, GlareBackendRequest::automatic,
     [](const GlareBackendSettings& settings) {
       return settings.frames.has_value() && settings.frames->psf.phase == PhaseForm::defocus;
     },
     always_available, make_planned, cpu_taken, planned_note},
    {GlareBackendKind::cpu_float64, GlareBackendRequest::cpu,
     [](const GlareBackendSettings& settings) { return settings.cpu_precision == FftPrecision::float64; },
     always_available, make_cpu, cpu_taken, no_note},
    {GlareBackendKind::cpu_float32, GlareBackendRequest::cpu,
     [](const GlareBackendSettings& settings) { return settings.cpu_precision == FftPrecision::float32; },
     always_available, make_cpu, cpu_taken, no_note},
};

}  // namespace

GlareBackendChoice create_glare_backend(GlareBackendRequest request, const GlareBackendSettings& settings) {
  const bool automatic = request == GlareBackendRequest::automatic;
  std::string refused;  // why the candidates before the one taken could not run here
  for (const Candidate& candidate : kCandidates) {
    if (!(automatic || candidate.answers == request) || !candidate.serves(settings)) continue;
    Probe probe;
    if (automatic) {
      if (const std::optional<std::string> why = candidate.unavailable(settings, probe)) {
        refused += (refused.empty() ? "" : "; ") + *why;
        continue;
      }
    }
    GlareBackendChoice choice;
    choice.backend = candidate.make(settings, probe);
    choice.kind = candidate.kind;
    choice.reason = std::string("glare backend ") + (automatic ? "auto picked " : "") + std::string(spelling(candidate.kind)) +
                    ": " + (refused.empty() ? candidate.taken(settings, probe, automatic) : refused) + ".";
    if (const std::string note = candidate.note(); !note.empty()) choice.reason += " " + note;
    return choice;
  }
  // Unreachable: cpu float64 or float32 serves every precision and is always available.
  throw std::logic_error("glare backend: no candidate for '" + std::string(spelling(request)) + "'");
}

ImageRGBA apply_glare(GlareBackend& backend, const ImageRGBA& image, double image_degrees_per_pixel,
                      const ApertureGeometry& geometry, const PsfOptions& options) {
  if (!geometry.glare_enabled) return image;  // control: no glare, the stimulus as it is
  const Psf psf = backend.psf(geometry, options);
  return backend.convolve(image, resample_psf_to_display(psf, image_degrees_per_pixel));
}

}  // namespace glarelab
