#pragma once
// The glare engine's compute seam (DESIGN.md: "GL compute shaders and a CPU double-precision path
// behind one interface, so each checks the other"). Both backends take the same aperture geometry
// and options and return the same Psf (glare/wave/psf.h) and ImageRGBA; tests compare them.
//
// Choosing: create_glare_backend("cpu" | "gl" | "auto"). On a hardware GPU the GL path is the fast
// one; on a software rasteriser (Mesa llvmpipe/softpipe/swrast, VMware SVGA3D) the GL path runs on
// the same CPU cores and is slower than FFTW there (3x for the PSF, 15x for the convolution at
// N = 1024 on llvmpipe, docs/PERFORMANCE.md), so `auto` takes the CPU.
#include <memory>
#include <string>

#include "core/gl/gl_context.h"
#include "core/image.h"
#include "glare/eye/aperture_geometry.h"
#include "glare/cpu/fft.h"
#include "glare/wave/fresnel.h"
#include "glare/wave/psf.h"

namespace glarelab {

struct PsfOptions {
  int grid_px = 512;                // N; the GL backend takes powers of two 16..4096
  double aperture_width_mm = 10.0;  // side of the pupil-plane grid
  int supersampling = 2;            // aperture sub-samples per pixel side
  double wavelength_nm = 575.0;     // the one wavelength, or the reference wavelength when spectral
  bool spectral = false;            // R, G, B by the chromatic blur (Ritschel et al. 2009, section 5)
  int wavelength_samples = 32;
  // Phase before the FFT. The GL backend has none and defocus; "paper" (Eq. 3, d = 24 mm) is CPU only.
  PhaseForm phase = PhaseForm::defocus;
  // The observer's refraction is modelled (docs/REFRACTION.md): a spectral PSF takes one FFT per
  // wavelength with the eye's longitudinal chromatic aberration (glare/wave/chromatic_psf.h) even when
  // geometry.refraction_error is zero. A non-zero refraction_error alone does the same on the CPU.
  // Only the CPU backend computes it (a GL or planned path ignoring it is not used for it).
  bool observer_refraction = false;
};

class GlareBackend {
 public:
  virtual ~GlareBackend() = default;
  virtual std::string name() const = 0;  // "cpu float64", "cpu float32", "gl"
  // Throws std::invalid_argument naming the backend for options it cannot take.
  virtual Psf psf(const ApertureGeometry& geometry, const PsfOptions& options) = 0;
  // Linear convolution (no wrap-around) of R, G, B with the PSF at the image's pixel scale; alpha
  // passes through. Refuses NaN, Inf and negative pixels (glare/image_sanitiser.h repairs them).
  virtual ImageRGBA convolve(const ImageRGBA& image, const Psf& psf) = 0;
  // A non-empty warning from the last psf() call (an aliased phase), else empty.
  virtual std::string last_warning() const { return {}; }
};

struct GlareBackendSettings {
  FftPrecision cpu_precision = FftPrecision::float64;  // float32 for speed, float64 for reference
  // Makes the OpenGL context the GL path works in (runner/display/compute_context.h gives the
  // program's). Empty: no GL here; "gl" is refused and "auto" takes the CPU.
  GlContextFactory gl_context;
};

struct GlareBackendChoice {
  std::unique_ptr<GlareBackend> backend;
  std::string reason;  // one sentence: what was picked and why
};

// True for renderers that rasterise in software (GL_RENDERER strings of Mesa's llvmpipe, softpipe
// and swrast, and VMware's SVGA3D).
bool is_software_renderer(const std::string& gl_renderer);

// "cpu", "gl" or "auto"; throws std::invalid_argument for another name, and DisplayError (from the
// GL context factory) when "gl" is asked for and no OpenGL 4.5 context can be made. "auto" never
// throws for want of GL: without a context it takes the CPU and says so.
GlareBackendChoice create_glare_backend(const std::string& name, const GlareBackendSettings& settings = {});

// Applies one glare condition to an image whose pixels subtend image_degrees_per_pixel: the control
// condition (geometry.glare_enabled false) returns the image itself, bit for bit, without calling the
// backend; otherwise the PSF is computed, mapped onto the image's pixel scale (glare/wave/psf_scale.h) and
// convolved.
ImageRGBA apply_glare(GlareBackend& backend, const ImageRGBA& image, double image_degrees_per_pixel,
                      const ApertureGeometry& geometry, const PsfOptions& options);

}  // namespace glarelab
