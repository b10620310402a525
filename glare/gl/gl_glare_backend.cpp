#include "glare/gl/gl_glare_backend.h"

#include <stdexcept>

#include "core/errors.h"

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
  if (options.phase == PhaseForm::none) drawn.defocus_dioptres = 0.0;  // Fraunhofer: no phase
  return options.spectral ? psf_->spectral(drawn, options.wavelength_samples, options.wavelength_nm)
                          : psf_->monochromatic(drawn, options.wavelength_nm);
}

ImageRGBA GlGlareBackend::convolve(const ImageRGBA& image, const Psf& psf) {
  context_->make_current();
  return convolution_->convolve(image, psf);
}

}  // namespace glarelab::gl
