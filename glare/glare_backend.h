#pragma once
// The glare engine's compute seam (docs/ARCHITECTURE.md, "Seams": GL compute shaders and a CPU
// double-precision path behind one interface, so that each checks the other). Every backend takes the same aperture geometry
// and options and returns the same Psf (glare/wave/psf.h) and ImageRGBA; tests compare them.
//
// Kinds (glare/glare_backend_kind.h): cpu float64, the reference that tests and `psf --backend cpu`
// use; cpu float32; cpu float32 planned, a session's frames on the CPU (glare/cpu/float_glare.h:
// plans and buffers kept, PSFs made at the display's pixel scale); gl, OpenGL 4.5 compute.
//
// Choosing: create_glare_backend, one table of candidates in glare_backend.cpp. On a hardware GPU
// the GL path is the fast one; on a software rasteriser (Mesa llvmpipe/softpipe/swrast, VMware
// SVGA3D) the GL path runs on the same CPU cores and is slower than FFTW there (docs/PERFORMANCE.md,
// "Measurements behind the code's choices"), so `auto` takes the CPU.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/gl/gl_context.h"
#include "core/image.h"
#include "glare/eye/aperture_geometry.h"
#include "glare/cpu/fft.h"
#include "glare/wave/fresnel.h"
#include "glare/glare_backend_kind.h"
#include "glare/cpu/float_convolution.h"
#include "glare/cpu/lit_regions.h"
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
  // geometry.refraction_error is zero. A non-zero refraction_error alone does the same
  // (takes_chromatic_psf). Every backend computes it: the CPU FFTW backends
  // (glare/wave/chromatic_psf.h), the planned float32 path (glare/cpu/planned_chromatic_psf.h) and the GL
  // backend (GlPsf::chromatic).
  bool observer_refraction = false;
};

class GlareBackend {
 public:
  virtual ~GlareBackend() = default;
  virtual GlareBackendKind kind() const = 0;
  std::string name() const { return std::string(spelling(kind())); }  // "cpu float64", ..., "gl"
  // Throws std::invalid_argument naming the backend for options it cannot take.
  virtual Psf psf(const ApertureGeometry& geometry, const PsfOptions& options) = 0;
  // Linear convolution (no wrap-around) of R, G, B with the PSF at the image's pixel scale; alpha
  // passes through. Refuses NaN, Inf and negative pixels (glare/image_sanitiser.h repairs them).
  virtual ImageRGBA convolve(const ImageRGBA& image, const Psf& psf) = 0;
  // convolve() left on the GPU where this backend works there (the GL backend): the name of a GL
  // shader storage buffer in its context holding the result (RGBA32F, ImageRGBA's layout, row 0
  // first), nothing read back, valid until the backend's next call; 0: this backend keeps nothing
  // on a GPU (the caller convolves on the host).
  // `image_token`: 0, or a token the caller gives this image and no other, so that a backend keeping
  // the image's spectrum knows it again without comparing its pixels (GlConvolutionOptions).
  virtual unsigned convolve_on_gpu(const ImageRGBA& /*image*/, const Psf& /*psf*/, std::uint64_t /*image_token*/) {
    return 0;
  }
  // The last convolution's stages timed on the GPU's clock (timer queries), seconds, in the order
  // they ran; empty for a backend on the CPU.
  virtual std::vector<std::pair<std::string, double>> last_gpu_stages_s() const { return {}; }
  // A non-empty warning from the last psf() call (an aliased phase), else empty.
  virtual std::string last_warning() const { return {}; }
  // The PSF on the pixels of a display whose centre pixel subtends display_degrees_per_pixel:
  // psf() mapped onto them (glare/wave/psf_scale.h). The planned path computes it at that scale directly.
  virtual Psf display_psf(const ApertureGeometry& geometry, const PsfOptions& options, double display_degrees_per_pixel);
  // The glare of the lit boxes of `frame` (glare/cpu/lit_regions.h: every pixel outside them black, no
  // two nearer than the PSF's size) written into `out` (frame's size, holding frame), alpha
  // untouched: outside the boxes grown by the PSF's reach the exact result is 0, what the frame
  // holds. Here each grown box (boxes_reached) is cropped and convolved; the planned path
  // convolves each box's whole linear convolution into place (CpuFloatGlare::convolve_regions).
  virtual void convolve_regions(const ImageRGBA& frame, const std::vector<PixelRect>& boxes, const Psf& display_psf,
                                ImageRGBA& out);
  // convolve_regions into `out` made here from a copy of `frame`: R, G, B the boxes' glare where it
  // reaches and the frame's own elsewhere, alpha the frame's, then `finish` called once on every row
  // segment of `out`, from any thread (a per-pixel pass, such as the hybrid eye's far field added
  // and the energies turned back into luminance, that the planned path does while each row it
  // writes is in cache instead of in another pass over the frame). `frame_token`: non-zero names
  // the pixels of `frame` (the same token, the same pixels, while the caller uses it), so that a
  // kept spectrum of the same pixels is taken without comparing them; 0: compared. `added_to`
  // (the frame's size), when given: `out` is made from a copy of it instead, and R, G, B of the
  // convolution (the boxes' glare, the frame's own elsewhere) are added to its own; alpha is its.
  virtual void convolve_regions_finished(const ImageRGBA& frame, const std::vector<PixelRect>& boxes,
                                         const Psf& display_psf, ImageRGBA& out, const RowFinish& finish,
                                         std::uint64_t frame_token = 0, const ImageRGBA* added_to = nullptr);
};

// Whether a spectral PSF of this aperture takes one FFT per wavelength with the eye's LCA
// (glare/wave/chromatic_psf.h) instead of the scaled reference (glare/wave/spectral_psf.h), which is
// exact only for a phase that does not depend on wavelength: the observer's refraction is modelled
// (options.observer_refraction) or the aperture carries a refraction error. Every backend decides
// by this one rule.
bool takes_chromatic_psf(const ApertureGeometry& geometry, const PsfOptions& options);

// Each box grown by the reach of a PSF psf_size_px across (M/2 before, M - 1 - M/2 <= M/2 after),
// clipped to a frame of width_px x height_px: where the box's glare lands.
std::vector<PixelRect> boxes_reached(const std::vector<PixelRect>& boxes, int psf_size_px, int width_px, int height_px);

// What a session's frames need of the planned float32 path: the PSFs' layout and the display's scale.
struct GlareFrameLayout {
  PsfOptions psf;  // grid, aperture width, supersampling, reference wavelength, wavelength samples
  double display_degrees_per_pixel = 0.0;  // at the display's centre (glare/wave/psf_scale.h)
};

struct GlareBackendSettings {
  FftPrecision cpu_precision = FftPrecision::float64;  // "cpu": float32 for speed, float64 for reference
  // Makes the OpenGL context the GL path works in (runner/display/compute_context.h gives the
  // program's). Empty: no GL here; "gl" is refused and "auto" takes the CPU.
  GlContextFactory gl_context;
  // The PSF grid to come: "auto" takes GL only for the GL PSF's grids (powers of two from 16 to
  // 4096). 0: not known, not checked (the GL path refuses other sizes when it computes).
  int grid_px = 0;
  // A session's frames: "auto" on the CPU takes the planned float32 path for this layout. Nothing:
  // the float64 reference.
  std::optional<GlareFrameLayout> frames = std::nullopt;
  // false: the request is the caller's default, no backend was named (the reason says so).
  bool named = true;
};

struct GlareBackendChoice {
  std::unique_ptr<GlareBackend> backend;
  GlareBackendKind kind = GlareBackendKind::cpu_float64;
  std::string reason;  // one sentence: what was picked and why
};

// True for renderers that rasterise in software (GL_RENDERER strings of Mesa's llvmpipe, softpipe
// and swrast, and VMware's SVGA3D).
bool is_software_renderer(const std::string& gl_renderer);

// The one place a backend is chosen. "cpu" and "gl" make that backend (cpu: of settings.cpu_precision);
// "gl" throws DisplayError (from the GL context factory) when no OpenGL 4.5 context can be made.
// "auto" takes the first candidate that can run here (gl, then the planned path for a session's
// frames, then cpu float64) and never throws for want of GL: the reason says why each one before
// it could not.
GlareBackendChoice create_glare_backend(GlareBackendRequest request, const GlareBackendSettings& settings = {});

// Applies one glare condition to an image whose pixels subtend image_degrees_per_pixel: the control
// condition (geometry.glare_enabled false) returns the image itself, bit for bit, without calling the
// backend; otherwise the PSF is computed, mapped onto the image's pixel scale (glare/wave/psf_scale.h) and
// convolved.
ImageRGBA apply_glare(GlareBackend& backend, const ImageRGBA& image, double image_degrees_per_pixel,
                      const ApertureGeometry& geometry, const PsfOptions& options);

}  // namespace glarelab
