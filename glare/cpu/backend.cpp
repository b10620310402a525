#include "glare/cpu/backend.h"

#include <stdexcept>

#include "glare/wave/chromatic_psf.h"
#include "glare/cpu/psf.h"
#include "glare/wave/spectral_psf.h"

namespace glarelab {

CpuGlareBackend::CpuGlareBackend(FftPrecision precision, double bright_threshold) : precision_(precision) {
  convolution_.precision = precision;
  convolution_.bright_threshold = bright_threshold;
}

GlareBackendKind CpuGlareBackend::kind() const {
  return precision_ == FftPrecision::float64 ? GlareBackendKind::cpu_float64 : GlareBackendKind::cpu_float32;
}

Psf CpuGlareBackend::psf(const ApertureGeometry& geometry, const PsfOptions& options) {
  if (takes_chromatic_psf(geometry, options)) {
    // The scaled reference PSF (glare/wave/spectral_psf.h) holds only for a phase that does not depend on
    // wavelength; the refraction's phase pi p^T E p / lambda and the eye's LCA do, so every
    // wavelength gets its own FFT (Thibos et al. 1992 LCA; docs/REFRACTION.md).
    if (options.phase != PhaseForm::defocus)
      throw std::invalid_argument("glare/cpu backend: the observer's refraction is a power error and needs the "
                                  "defocus phase form, not '" + std::string(phase_form_name(options.phase)) + "'");
    ChromaticPsfOptions chromatic;
    chromatic.raster.grid_px = options.grid_px;
    chromatic.raster.aperture_width_mm = options.aperture_width_mm;
    chromatic.raster.supersampling = options.supersampling;
    chromatic.reference_wavelength_nm = options.wavelength_nm;
    chromatic.wavelength_samples = options.wavelength_samples;
    chromatic.precision = precision_;
    ChromaticPsfResult result = compute_chromatic_psf(geometry, chromatic);
    last_warning_ = result.sampling_warning.empty()
                        ? std::string()
                        : result.sampling_warning + "; " + std::to_string(result.aliased_wavelengths) + " of " +
                              std::to_string(options.wavelength_samples) + " wavelengths aliased";
    return std::move(result.spectral.psf);
  }
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
