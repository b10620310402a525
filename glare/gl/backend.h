#pragma once
// The GL glare backend: glare/gl/psf.h (aperture, FFT, spectral weights) and glare/gl/convolution.h on an
// OpenGL 4.5 context it is handed and owns (core/gl/gl_context.h). The
// GlPsf is kept while the grid, aperture width and supersampling stay the same. Phase forms: none
// and defocus (the paper's Eq. 3 phase cannot be sampled on any GL grid; docs/GLARE_OPTICS.md);
// defocus is the eye's whole power error, ApertureGeometry::total_power_error() (defocus plus the
// observer's sphero-cylindrical refraction error), none drops both.
#include <memory>

#include "glare/gl/convolution.h"
#include "glare/gl/psf.h"
#include "glare/glare_backend.h"
#include "core/gl/gl_context.h"

namespace glarelab::gl {

class GlGlareBackend : public GlareBackend {
 public:
  // context: the context to work in, made current for every call (DisplayError when null).
  explicit GlGlareBackend(std::unique_ptr<GlContext> context);
  ~GlGlareBackend() override;
  GlareBackendKind kind() const override { return GlareBackendKind::gl; }
  Psf psf(const ApertureGeometry& geometry, const PsfOptions& options) override;
  ImageRGBA convolve(const ImageRGBA& image, const Psf& psf) override;
  unsigned convolve_on_gpu(const ImageRGBA& image, const Psf& psf, std::uint64_t image_token) override;
  std::vector<std::pair<std::string, double>> last_gpu_stages_s() const override { return last_report_.gpu_stages_s; }
  const GlInfo& gl_info() const { return context_->gl_info(); }
  // The sampling check of the last psf() (glare/wave/fresnel.h, or glare/refraction/astigmatic_phase.h's strongest meridian
  // for an astigmatic error): the warning when the phase aliases on the grid, else empty.
  std::string last_warning() const override { return last_warning_; }

 private:
  std::unique_ptr<GlContext> context_;
  std::unique_ptr<GlPsf> psf_;
  PsfOptions psf_layout_;  // grid, width and supersampling psf_ was made for
  std::unique_ptr<GlConvolution> convolution_;
  std::string last_warning_;
  GlConvolutionReport last_report_;  // the last convolution's
};

}  // namespace glarelab::gl
