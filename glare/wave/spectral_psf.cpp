#include "glare/wave/spectral_psf.h"

#include <stdexcept>

#include "glare/wave/cie_cmf.h"

namespace glarelab {

SpectralPsfResult spectral_psf_from_reference(const Psf& reference, const SpectralPsfOptions& options) {
  if (reference.channels != 1) throw std::invalid_argument("glare/wave/spectral_psf: the reference PSF must have one channel");
  if (options.wavelength_samples < 1) throw std::invalid_argument("glare/wave/spectral_psf: need at least one wavelength sample");
  if (!(options.reference_wavelength_nm > 0.0)) throw std::invalid_argument("glare/wave/spectral_psf: reference wavelength must be > 0");
  XyzPlanes xyz(reference.size_px);
  for (const SpectralSample& sample : spectral_samples(options.wavelength_samples)) {
    // Ritschel et al. 2009, section 5: lambda_i = 380 + i (770 - 380) / n nm (glare/wave/cie_cmf.h); F_i is the
    // reference PSF read at x lambda_ref / lambda_i.
    accumulate_resampled_psf(reference, options.reference_wavelength_nm / sample.wavelength_nm,
                             cie1931_cmf(sample.wavelength_nm), xyz);
  }
  return rec709_psf_from_xyz(xyz, reference.degrees_per_pixel, "glare/wave/spectral_psf");
}

}  // namespace glarelab
