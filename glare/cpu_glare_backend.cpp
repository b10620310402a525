#include "glare/cpu_glare_backend.h"

#include "glare/psf_cpu.h"
#include "glare/spectral_psf.h"

namespace glarelab {

CpuGlareBackend::CpuGlareBackend(FftPrecision precision, double bright_threshold) : precision_(precision) {
  convolution_.precision = precision;
  convolution_.bright_threshold = bright_threshold;
}

std::string CpuGlareBackend::name() const { return std::string("cpu ") + fft_precision_name(precision_); }

Psf CpuGlareBackend::psf(const ApertureGeometry& geometry, const PsfOptions& options) {
  MonochromaticPsfOptions mono;
  mono.raster.grid_px = options.grid_px;
  mono.raster.aperture_width_mm = options.aperture_width_mm;
  mono.raster.supersampling = options.supersampling;
  mono.wavelength_nm = options.wavelength_nm;
  mono.phase = options.phase;
  mono.precision = precision_;
  MonochromaticPsfResult result = compute_monochromatic_psf(geometry, mono);
  last_warning_ = result.sampling_warning;
  if (!options.spectral) return std::move(result.psf);
  SpectralPsfOptions spectral;
  spectral.wavelength_samples = options.wavelength_samples;
  spectral.reference_wavelength_nm = options.wavelength_nm;
  return spectral_psf_from_reference(result.psf, spectral).psf;
}

ImageRGBA CpuGlareBackend::convolve(const ImageRGBA& image, const Psf& psf) {
  return convolve_image_cpu(image, psf, convolution_);
}

}  // namespace glarelab
