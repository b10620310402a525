#pragma once
// The monochromatic PSF of glare/cpu/psf.h (Ritschel et al. 2009, Eq. 3: PSF = K |FFT(A E)|^2, shifted so
// the DC term sits at (N/2, N/2)) in float32 for a stream of frames: the FFTW plan and every buffer
// made once for one grid size (glare/cpu/pupil_spectrum.h), the aperture rasterised and the power
// spectrum taken on kGlareCpuThreads threads. Checked against the float64 path of glare/cpu/psf.h (tests/glare_cpu_float_test.cpp).
#include <complex>
#include <string>
#include <vector>

#include "glare/eye/aperture_geometry.h"
#include "glare/eye/aperture_raster.h"
#include "glare/refraction/dioptric_power.h"
#include "glare/cpu/fftw_float_plan.h"
#include "glare/cpu/pupil_spectrum.h"
#include "glare/wave/fresnel.h"
#include "glare/wave/psf.h"

namespace glarelab {

struct CpuFloatPsfSettings {
  ApertureRasterOptions raster;  // grid, aperture width, supersampling (threads: taken from below)
  double wavelength_nm = 575.0;
  PhaseForm phase = PhaseForm::defocus;
  int threads = kGlareCpuThreads;
};

class CpuFloatPsf {
 public:
  explicit CpuFloatPsf(const CpuFloatPsfSettings& settings);
  int grid_px() const { return settings_.raster.grid_px; }
  double degrees_per_pixel() const;

  // Stage 1: the aperture of `geometry` (glare/eye/aperture_raster.h, the same grid bit for bit).
  void rasterise(const ApertureGeometry& geometry);
  // Stage 2: the pupil phase, the N x N FFT, |F|^2 shifted into power_column_major(). Throws ClosedApertureError
  // for an aperture that transmits nothing; an aliased phase leaves sampling_warning() non-empty.
  // A spherical defocus (glare/wave/fresnel.h's phase of settings.phase):
  void transform(double pupil_diameter_mm, double defocus_dioptres);
  // The eye's power error E (ApertureGeometry::total_power_error()). With the defocus form and an
  // astigmatic E (an xy term, or E_xx != E_yy) the phase is glare/refraction/astigmatic_phase.h's
  // (pi / lambda)(E_xx x^2 + 2 E_xy x y + E_yy y^2), checked by check_power_error_sampling;
  // otherwise it is transform(pupil_diameter_mm, E_xx), bit for bit (the forms none and paper take
  // no error, as they take no defocus).
  void transform(double pupil_diameter_mm, const DioptricPower& error);
  // The same at another wavelength than settings.wavelength_nm, with the same plan and buffers (the
  // spectral PSF with longitudinal chromatic aberration transforms once per wavelength:
  // glare/cpu/planned_chromatic_psf.h). The two-argument form is this one at settings.wavelength_nm. Throws
  // std::invalid_argument for a wavelength that is not positive.
  void transform(double pupil_diameter_mm, const DioptricPower& error, double wavelength_nm);

  // |FFT|^2 shifted, unnormalised (K is left to whoever normalises: the spectral PSF normalises its
  // channels itself), N x N column-major: pixel (x, y) at [x N + y]. The FFT leaves its result
  // transposed (below), so this layout is written in order; the spectral stages read it as it is.
  const float* power_column_major() const { return spectrum_.power_column_major(); }
  const std::string& sampling_warning() const { return spectrum_.sampling_warning(); }
  const ApertureGrid& aperture() const { return grid_; }
  PhaseForm phase() const { return settings_.phase; }
  // The pupil function the last transform() handed the FFT, N x N row-major, row 0 at the top
  // (the rows that cannot meet the pupil are 0).
  const std::complex<float>* field() const { return spectrum_.field(); }
  // The power normalised to sum 1 as a one-channel Psf (glare/cpu/psf.h's result); allocates, for checks.
  Psf monochromatic_psf() const;

 private:
  CpuFloatPsfSettings settings_;
  ApertureGrid grid_;
  PupilSpectrum<float> spectrum_;  // the transform, its plan and buffers (glare/cpu/pupil_spectrum.h)
};

}  // namespace glarelab
