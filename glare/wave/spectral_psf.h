#pragma once
// Spectral PSF by the chromatic blur of Ritschel et al. 2009, section 5: n wavelengths
//   lambda_i = 380 nm + i (770 nm - 380 nm) / n,  i = 0..n-1,
// each PSF a copy of the reference PSF F_ref (computed once at lambda_ref, 575 nm in the paper)
// scaled in angle, F_lambda(theta) = (lambda_ref/lambda)^2 F_ref(theta lambda_ref / lambda) (the
// Jacobian keeps every wavelength's PSF at unit energy, which the paper's sum leaves implicit),
// read with bilinear interpolation on the reference grid, weighted with the CIE 1931 CMFs to XYZ,
// converted to linear Rec.709. Negative Rec.709 values (spectral colours outside the Rec.709 gamut)
// are clamped to 0 before each channel is normalised to sum 1; the clamped fraction is reported.
#include "glare/wave/psf.h"
#include "glare/wave/spectral_accumulation.h"

namespace glarelab {

struct SpectralPsfOptions {
  int wavelength_samples = 32;        // n (Ritschel: 32 is the best trade-off)
  double reference_wavelength_nm = 575.0;
};

// SpectralPsfResult: glare/wave/spectral_accumulation.h.

// `reference` is a one-channel PSF computed at options.reference_wavelength_nm.
SpectralPsfResult spectral_psf_from_reference(const Psf& reference, const SpectralPsfOptions& options);

}  // namespace glarelab
