#pragma once
// Monochromatic PSF on the CPU (Ritschel et al. 2009, Eq. 3): PSF = K |FFT(A E)|^2, shifted so the
// DC term sits at pixel (N/2, N/2), with K chosen so the PSF sums to 1. Angular pixel size in the
// Fraunhofer limit: theta_px = lambda / (N dx) radians (docs/GLARE_OPTICS.md derives it).
#include <string>

#include "glare/eye/aperture_geometry.h"
#include "glare/eye/aperture_raster.h"
#include "glare/refraction/dioptric_power.h"
#include "glare/cpu/fft.h"
#include "glare/wave/fresnel.h"
#include "glare/wave/psf.h"

namespace glarelab {

struct MonochromaticPsfOptions {
  ApertureRasterOptions raster;
  double wavelength_nm = 575.0;  // Ritschel's reference wavelength (section 5)
  PhaseForm phase = PhaseForm::defocus;  // uses ApertureGeometry::defocus_dioptres (0 = in focus)
  bool strict_sampling = false;  // aliased phase: throw instead of returning a warning
  FftPrecision precision = FftPrecision::float64;
};

struct MonochromaticPsfResult {
  Psf psf;                          // one channel "Y", sums to 1
  double unnormalised_sum = 0.0;    // sum |FFT|^2 before K (= N^2 sum |A|^2 by Parseval)
  double aperture_energy = 0.0;     // sum |A|^2
  std::string sampling_warning;     // non-empty when the phase is aliased (and strict_sampling is off)
};

// Angular size (degrees) of one PSF pixel for an aperture grid of side N dx = aperture_width_mm.
double psf_degrees_per_pixel(double wavelength_nm, double aperture_width_mm);

// Diameter, in PSF pixels, of the Airy core of a clear pupil of diameter D on an aperture grid of side
// W: the first dark ring is at 1.22 lambda / D (Born and Wolf, Principles of Optics, 8.5.2) and a PSF
// pixel is lambda / W (above), so the core is 2.44 W / D pixels across, whatever lambda and N. When it
// is wider than the grid, the grid holds no more than a blur of its centre (a pupil spanning fewer
// than 2.44 aperture pixels); docs/GLARE_OPTICS.md "Grid limits".
double airy_core_diameter_px(double pupil_diameter_mm, double aperture_width_mm);

// |FFT(field)|^2 of an N x N complex field, fftshifted (DC to (N/2, N/2)), unnormalised.
std::vector<double> shifted_power_spectrum(std::vector<std::complex<double>> field, int grid_px, FftPrecision precision);

// The phase is that of geometry.total_power_error() (the defocus plus the observer's refraction error):
// when geometry.astigmatic(), the astigmatic phase of glare/refraction/astigmatic_phase.h, checked for aliasing
// along its strongest meridian; otherwise glare/wave/fresnel.h's quadratic phase of the spherical error, which
// for a zero refraction error is exactly the defocus_dioptres overload below. A refraction error needs
// PhaseForm::defocus (std::invalid_argument otherwise): "paper" and "none" have no place for it.
MonochromaticPsfResult compute_monochromatic_psf(const ApertureGeometry& geometry, const MonochromaticPsfOptions& options);
// The same from an already rasterised aperture (the rasteriser does not depend on wavelength).
MonochromaticPsfResult compute_monochromatic_psf(const ApertureGrid& grid, double pupil_diameter_mm,
                                                 double defocus_dioptres, const MonochromaticPsfOptions& options);
// The same with a sphero-cylindrical power error E (dioptres, observer frame; glare/refraction/dioptric_power.h):
// a spherical E gives the defocus overload's PSF with E's power; any other, the astigmatic phase.
MonochromaticPsfResult compute_monochromatic_psf(const ApertureGrid& grid, double pupil_diameter_mm,
                                                 const DioptricPower& power_error, const MonochromaticPsfOptions& options);

}  // namespace glarelab
