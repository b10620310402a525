#pragma once
// The CPU glare backend: aperture_raster + FFTW (glare/cpu/psf.h), glare/wave/spectral_psf.h, glare/cpu/convolution.h.
// float64 is the reference the GL path is checked against; float32 the faster (docs/PERFORMANCE.md).
// With the observer's refraction (geometry.refraction_error, PsfOptions::observer_refraction) a
// spectral PSF is glare/wave/chromatic_psf.h's, one FFT per wavelength with the eye's LCA.
#include "glare/cpu/convolution.h"
#include "glare/glare_backend.h"

namespace glarelab {

class CpuGlareBackend : public GlareBackend {
 public:
  explicit CpuGlareBackend(FftPrecision precision = FftPrecision::float64, double bright_threshold = 0.0);
  GlareBackendKind kind() const override;
  Psf psf(const ApertureGeometry& geometry, const PsfOptions& options) override;
  ImageRGBA convolve(const ImageRGBA& image, const Psf& psf) override;
  std::string last_warning() const override { return last_warning_; }

 private:
  FftPrecision precision_;
  ConvolutionOptions convolution_;
  std::string last_warning_;
};

}  // namespace glarelab
