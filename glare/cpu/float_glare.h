#pragma once
// The planned float32 CPU glare path (glare/cpu/float_psf.h -> glare/cpu/float_spectral_psf.h ->
// glare/cpu/float_convolution.h) as a frame-by-frame service for sessions: the eye's aperture to the
// spectral PSF at the display's pixel scale, and that PSF convolved with a frame. Plans and buffers
// are made once per grid and per frame size; the frame's spectrum is kept while the same frame
// comes again (a static scene within a trial: 3 forward + 3 inverse transforms per frame instead
// of 9). Its frame error against the float64 reference is below 1e-6 relative L2 (glarelab bench;
// tests/glare_cpu_float_test.cpp and tests/glare_stage_test.cpp check it through this class).
// It is the GlareBackend of kind cpu float32 planned (glare/glare_backend.h), which "auto" picks for
// a session's frames on the CPU. A PSF with the observer's refraction (takes_chromatic_psf) takes one
// float32 FFT per wavelength with the eye's LCA (glare/cpu/planned_chromatic_psf.h), the float64
// reference's operator (glare/wave/chromatic_psf.h) within 1e-5 of its peak
// (tests/refraction_float_engine_test.cpp).
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/image.h"
#include "glare/eye/aperture_geometry.h"
#include "glare/cpu/float_convolution.h"
#include "glare/cpu/planned_chromatic_psf.h"
#include "glare/cpu/float_psf.h"
#include "glare/cpu/float_spectral_psf.h"
#include "glare/glare_backend.h"
#include "glare/cpu/lit_regions.h"
#include "glare/wave/psf.h"

namespace glarelab {

struct CpuFloatGlareSettings {
  int grid_px = 256;
  double aperture_width_mm = 10.0;
  int supersampling = 2;
  double reference_wavelength_nm = 575.0;
  int wavelength_samples = 32;
  double display_degrees_per_pixel = 0.0;  // at the display's centre (glare/wave/psf_scale.h)
  // false: the scaled-reference spectral PSF (glare/cpu/float_spectral_psf.h), one FFT at the reference
  // wavelength, for every PSF the backend interface does not ask with a refraction
  // (takes_chromatic_psf). true: every PSF with the eye's longitudinal chromatic aberration, one FFT
  // per wavelength with its own power error (glare/cpu/planned_chromatic_psf.h), box-resampled onto the
  // display (glare/wave/psf_scale.h) as the float64 path resamples compute_chromatic_psf.
  bool longitudinal_chromatic_aberration = false;
};

class CpuFloatGlare : public GlareBackend {
 public:
  // Throws PsfScaleError when the PSF cannot be shown at this display scale (glare/wave/psf_scale.h).
  explicit CpuFloatGlare(const CpuFloatGlareSettings& settings);
  GlareBackendKind kind() const override { return GlareBackendKind::cpu_float32_planned; }
  // The PSF on the aperture grid (float32 transforms, the defocus phase of the whole power error):
  // monochromatic; spectral by the reference's scaling (glare/wave/spectral_psf.h) of the float32
  // PSF; with the observer's refraction (takes_chromatic_psf) one float32 FFT per wavelength with the
  // eye's LCA. A session's frames take their spectral PSF at the display's scale (display_psf); this
  // is `glarelab psf`'s. A layout other than the settings' (grid, aperture width, supersampling,
  // reference wavelength, defocus phase, and for a spectral PSF the wavelengths) throws
  // std::invalid_argument.
  Psf psf(const ApertureGeometry& geometry, const PsfOptions& options) override;
  // display_psf(geometry) for `options` and a display scale that are the settings' (else
  // std::invalid_argument): the interface the frames of a session go through. With the observer's
  // refraction (takes_chromatic_psf) the PSF is the per-wavelength one whatever the settings say.
  Psf display_psf(const ApertureGeometry& geometry, const PsfOptions& options, double display_degrees_per_pixel) override;
  // The last PSF's sampling warning; per wavelength with how many aliased, as CpuGlareBackend says it.
  std::string last_warning() const override;
  // R, G, B at the display scale, each summing to 1. Throws ClosedApertureError when the lids
  // cover the whole pupil.
  Psf display_psf(const ApertureGeometry& geometry) { return display_psf(geometry, settings_.longitudinal_chromatic_aberration); }
  // The same, per wavelength with the eye's LCA when `chromatic`, else by the scaled reference.
  Psf display_psf(const ApertureGeometry& geometry, bool chromatic);
  // Linear convolution of R, G, B with a display-scale PSF (display_psf's size); alpha passes
  // through. Refuses NaN, Inf and negative pixels (std::invalid_argument), as convolve_image_cpu.
  ImageRGBA convolve(const ImageRGBA& image, const Psf& display_psf) override;
  // The glare of the lit boxes of `frame` (glare/cpu/lit_regions.h: every pixel outside them black, no
  // two nearer than the PSF's size) written into `out` (frame's size, holding frame): each box's
  // whole linear convolution with `display_psf`, the box grown by the PSF's reach, over R, G, B;
  // alpha untouched. Boxes of one size share one transform of the PSF, and each box's spectrum is
  // kept while the same pixels come again at that place in the list (a static scene). Refuses NaN,
  // Inf and negative pixels in the boxes (std::invalid_argument).
  void convolve_regions(const ImageRGBA& frame, const std::vector<PixelRect>& boxes, const Psf& display_psf,
                        ImageRGBA& out) override;
  // The same with `finish` done on each row of a box's glare as the inverse transform writes it
  // (in cache, on the convolution's threads) and on the rest of `out` after. A box's kept spectrum
  // made under the same non-zero `frame_token` is taken without comparing its pixels. With
  // `added_to`, the boxes' glare is added to its copy where it reaches; elsewhere the frame is
  // black (the boxes hold every lit pixel), so the copy is the sum there as it is.
  void convolve_regions_finished(const ImageRGBA& frame, const std::vector<PixelRect>& boxes, const Psf& display_psf,
                                 ImageRGBA& out, const RowFinish& finish, std::uint64_t frame_token = 0,
                                 const ImageRGBA* added_to = nullptr) override;
  // The phase sampling check of the last display_psf() (the eye's whole power error, defocus plus
  // refraction; glare/cpu/float_psf.h): the aliasing warning, or empty. With LCA, that of the most aliased
  // wavelength (glare/cpu/planned_chromatic_psf.h).
  const std::string& sampling_warning() const {
    return last_chromatic_ ? chromatic_->sampling_warning() : psf_.sampling_warning();
  }
  // Whether the last convolve() (convolve_regions(): every box) reused the kept frame spectrum.
  bool reused_scene() const { return reused_scene_; }

 private:
  CpuPlannedChromaticPsf& chromatic_psf();
  // Refuses options (and a display scale, when given) other than those it was made for.
  void check_layout(const PsfOptions& options, std::optional<double> display_degrees_per_pixel) const;

  CpuFloatGlareSettings settings_;
  CpuFloatPsf psf_;
  // The spectral PSF at the display's scale, made with the first such PSF (`psf`'s grid PSFs never need
  // its M x M sums).
  std::unique_ptr<CpuFloatSpectralPsf> spectral_;
  // Made with the first per-wavelength PSF (its per-wavelength tables), then kept.
  std::unique_ptr<CpuPlannedChromaticPsf> chromatic_;
  bool last_chromatic_ = false;  // the last PSF was chromatic_'s
  double display_degrees_per_pixel_ = 0.0;
  std::unique_ptr<CpuFloatConvolution> convolution_;
  int convolution_width_px_ = 0, convolution_height_px_ = 0, convolution_kernel_px_ = 0;
  ImageRGBA scene_;  // the frame whose spectrum the convolution holds
  bool reused_scene_ = false;
  // convolve_regions(): per box size, a `full` convolution with a slot per box of that size, and
  // the pixels each slot's spectrum was made from (the box cropped from its frame).
  struct RegionPlan {
    std::unique_ptr<CpuFloatConvolution> convolution;
    std::vector<ImageRGBA> pixels;
    std::vector<std::uint64_t> tokens;  // per slot, the frame token its spectrum was made under (0: none)
  };
  // convolve_regions with an optional finish of each written row and a frame token.
  void regions_into(const ImageRGBA& frame, const std::vector<PixelRect>& boxes, const Psf& display_psf, ImageRGBA& out,
                    const RowFinish* finish, std::uint64_t frame_token, FullWrite write = FullWrite::replace);
  std::map<std::pair<int, int>, RegionPlan> region_plans_;
  int region_kernel_px_ = 0;
};

}  // namespace glarelab
