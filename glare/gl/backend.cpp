#include "glare/gl/backend.h"

#include <stdexcept>

#include "core/errors.h"
#include "glare/refraction/astigmatic_phase.h"
#include "glare/wave/fresnel.h"

namespace glarelab::gl {

GlGlareBackend::GlGlareBackend(std::unique_ptr<GlContext> context) : context_(std::move(context)) {
  if (!context_) throw DisplayError("OpenGL: the glare engine's GL path was given no context");
  context_->make_current();
  convolution_ = std::make_unique<GlConvolution>();
}

GlGlareBackend::~GlGlareBackend() {
  // GL objects are deleted while their context is current, before the context goes.
  context_->make_current();
  psf_.reset();
  convolution_.reset();
}

Psf GlGlareBackend::psf(const ApertureGeometry& geometry, const PsfOptions& options) {
  if (options.phase == PhaseForm::paper)
    throw std::invalid_argument(
        "glare backend gl: the paper's Fresnel phase (Eq. 3, d = 24 mm) is CPU only; use --fresnel defocus or none");
  context_->make_current();
  if (!psf_ || psf_layout_.grid_px != options.grid_px || psf_layout_.aperture_width_mm != options.aperture_width_mm ||
      psf_layout_.supersampling != options.supersampling) {
    psf_.reset();
    psf_ = std::make_unique<GlPsf>(options.grid_px, options.aperture_width_mm, options.supersampling);
    psf_layout_ = options;
  }
  ApertureGeometry drawn = geometry;
  if (options.phase == PhaseForm::none) {  // Fraunhofer: no phase, neither defocus nor refraction
    drawn.defocus_dioptres = 0.0;
    drawn.refraction_error = DioptricPower{};
  }
  // The phase GlPsf loads is that of the whole power error; the check is the one the CPU makes
  // for the same error (glare/cpu/psf.h for a spherical one, the strongest meridian for an astigmatic one).
  const DioptricPower error = drawn.total_power_error();
  const double pupil_radius_mm = 0.5 * drawn.pupil_diameter_mm;
  const double pixel_mm = options.aperture_width_mm / options.grid_px;
  const PhaseSamplingReport sampling =
      drawn.astigmatic()
          ? check_power_error_sampling(error, options.wavelength_nm, pupil_radius_mm, pixel_mm, options.aperture_width_mm)
          : check_phase_sampling(phase_coefficient_per_m2(PhaseForm::defocus, options.wavelength_nm, error.xx()),
                                 pupil_radius_mm, pixel_mm, options.aperture_width_mm);
  last_warning_ = sampling.aliased ? sampling.warning : std::string();
  // The observer's refraction (as CpuGlareBackend decides it): one FFT per wavelength with the
  // eye's longitudinal chromatic aberration, GlPsf::chromatic (glare/wave/chromatic_psf.h on the GPU),
  // instead of the scaled reference, which is exact only for a wavelength-independent phase.
  if (options.phase != PhaseForm::none && takes_chromatic_psf(drawn, options)) {
    Psf chromatic = psf_->chromatic(drawn, options.wavelength_samples, options.wavelength_nm);
    last_warning_ = psf_->chromatic_sampling_warning();
    return chromatic;
  }
  return options.spectral ? psf_->spectral(drawn, options.wavelength_samples, options.wavelength_nm)
                          : psf_->monochromatic(drawn, options.wavelength_nm);
}

ImageRGBA GlGlareBackend::convolve(const ImageRGBA& image, const Psf& psf) {
  context_->make_current();
  return convolution_->convolve(image, psf, {}, &last_report_);
}

unsigned GlGlareBackend::convolve_on_gpu(const ImageRGBA& image, const Psf& psf, std::uint64_t image_token) {
  context_->make_current();
  GlConvolutionOptions options;
  options.image_token = image_token;
  return convolution_->convolve_on_gpu(image, psf, options, &last_report_);
}

}  // namespace glarelab::gl
