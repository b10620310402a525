#pragma once
// Spectral PSF of an eye with a refraction error and longitudinal chromatic aberration. The chromatic
// blur of glare/wave/spectral_psf.h scales one reference PSF per wavelength, which is exact only when the
// pupil phase does not depend on wavelength (Fraunhofer); a power error E gives the phase
// pi p^T E p / lambda, and the eye's power itself changes with wavelength (LCA), so here every
// wavelength sample gets its own FFT with its own error
//
//   E(lambda) = E_ref + [LCA(lambda) - LCA(lambda_ref)] I,
//
// LCA the eye's chromatic excess power of Thibos et al. 1992 (glare/refraction/chromatic_eye.h: positive toward
// the blue; E positive = too much power, glare/refraction/eye_refraction.h). E_ref is the error at the reference
// wavelength (the one the refraction is taken to be measured at). Each PSF_lambda (pixels of
// lambda / W radians) is resampled onto the reference grid (pixels of lambda_ref / W) and weighted with
// the CIE 1931 CMFs into linear Rec.709 exactly as glare/wave/spectral_psf.cpp does (glare/wave/spectral_accumulation.h), at
// Ritschel's wavelengths lambda_i = 380 + i (770 - 380) / n nm.
#include <string>

#include "glare/eye/aperture_geometry.h"
#include "glare/eye/aperture_raster.h"
#include "glare/cpu/fft.h"
#include "glare/wave/spectral_accumulation.h"

namespace glarelab {

struct ChromaticPsfOptions {
  ApertureRasterOptions raster;
  double reference_wavelength_nm = 575.0;  // lambda_ref: E_ref's wavelength and the output grid's
  int wavelength_samples = 32;             // n
  bool longitudinal_chromatic_aberration = true;  // false: E(lambda) = E_ref at every wavelength
  bool strict_sampling = false;            // an aliased phase at any wavelength: throw
  FftPrecision precision = FftPrecision::float64;
};

struct ChromaticPsfResult {
  SpectralPsfResult spectral;   // R, G, B on the reference grid, each channel sums to 1
  std::string sampling_warning;  // the most aliased wavelength's warning, empty when none aliases
  int aliased_wavelengths = 0;
};

// The power error (dioptres) the eye has at wavelength_nm: E_ref + LCA excess (or E_ref without LCA).
DioptricPower chromatic_power_error(const DioptricPower& reference_error, double wavelength_nm,
                                    const ChromaticPsfOptions& options);

// The spectral PSF of geometry (pupil, scatterers, total_power_error() as E_ref). Throws
// std::invalid_argument (naming "glare/wave/chromatic_psf") for n < 1 or a reference wavelength the LCA fit
// cannot take, and ClosedApertureError when no light passes.
ChromaticPsfResult compute_chromatic_psf(const ApertureGeometry& geometry, const ChromaticPsfOptions& options);

}  // namespace glarelab
