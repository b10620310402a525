#include "glare/cpu_float_chromatic_psf.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "glare/astigmatic_phase.h"
#include "glare/chromatic_eye.h"
#include "glare/psf_cpu.h"

namespace glarelab {
namespace {

int checked_grid(const CpuFloatChromaticSettings& settings) {
  if (settings.grid_px < 2 || settings.grid_px % 2 != 0)
    throw std::invalid_argument("glare/cpu_float_chromatic_psf: grid size must be even and >= 2");
  if (settings.wavelength_samples < 1)
    throw std::invalid_argument("glare/cpu_float_chromatic_psf: need at least one wavelength sample");
  if (!(settings.reference_wavelength_nm > 0.0))
    throw std::invalid_argument("glare/cpu_float_chromatic_psf: the reference wavelength must be > 0 nm");
  return settings.grid_px;
}

}  // namespace

CpuFloatChromaticPsf::CpuFloatChromaticPsf(const CpuFloatChromaticSettings& settings)
    : settings_(settings), xyz_(checked_grid(settings)) {
  for (const SpectralSample& sample : spectral_samples(settings.wavelength_samples)) {
    Wavelength wavelength;
    wavelength.wavelength_nm = sample.wavelength_nm;
    // Throws (glare/chromatic_eye) for a reference at or below the fit's pole, before any transform.
    wavelength.excess_dioptres = chromatic_power_excess_dioptres(sample.wavelength_nm, settings.reference_wavelength_nm);
    wavelength.cmf = cie1931_cmf(sample.wavelength_nm);
    wavelengths_.push_back(wavelength);
  }
  const int n = settings.grid_px;
  wavelength_psf_.size_px = n;
  wavelength_psf_.channels = 1;
  wavelength_psf_.values.assign(static_cast<std::size_t>(n) * n, 0.0);
}

double CpuFloatChromaticPsf::degrees_per_pixel() const {
  return psf_degrees_per_pixel(settings_.reference_wavelength_nm, settings_.aperture_width_mm);
}

SpectralPsfResult CpuFloatChromaticPsf::compute(CpuFloatPsf& psf, double pupil_diameter_mm,
                                                const DioptricPower& reference_error) {
  const int n = settings_.grid_px;
  if (psf.grid_px() != n || psf.aperture().aperture_width_mm != settings_.aperture_width_mm)
    throw std::invalid_argument("glare/cpu_float_chromatic_psf: the CpuFloatPsf has another grid or has not rasterised an aperture");
  const std::size_t count = static_cast<std::size_t>(n) * n;
  std::fill(xyz_.values.begin(), xyz_.values.end(), 0.0);
  sampling_warning_.clear();
  aliased_wavelengths_ = 0;
  double worst_step_rad = 0.0;
  for (const Wavelength& wavelength : wavelengths_) {
    // chromatic_psf.cpp's chromatic_power_error: E_ref + [LCA(lambda) - LCA(lambda_ref)] I.
    const DioptricPower error = reference_error + DioptricPower::spherical(wavelength.excess_dioptres);
    psf.transform(pupil_diameter_mm, error, wavelength.wavelength_nm);
    if (!psf.sampling_warning().empty()) {
      ++aliased_wavelengths_;
      const double step_rad = check_power_error_sampling(error, wavelength.wavelength_nm, 0.5 * pupil_diameter_mm,
                                                         psf.aperture().pixel_mm(), psf.aperture().aperture_width_mm)
                                  .max_phase_step_rad;
      if (step_rad > worst_step_rad) {
        worst_step_rad = step_rad;
        sampling_warning_ = psf.sampling_warning() + " (at " + std::to_string(wavelength.wavelength_nm) + " nm)";
      }
    }
    // The unit-sum PSF of psf_cpu.h (K = 1 / sum), as the reference accumulates it.
    const float* power = psf.power();
    double sum = 0.0;
    for (std::size_t k = 0; k < count; ++k) sum += power[k];
    const double inverse = 1.0 / sum;
    for (std::size_t k = 0; k < count; ++k) wavelength_psf_.values[k] = power[k] * inverse;
    // A PSF at lambda has pixels of lambda / W: reference pixel x lies at its pixel x lambda_ref / lambda.
    accumulate_resampled_psf(wavelength_psf_, settings_.reference_wavelength_nm / wavelength.wavelength_nm,
                             wavelength.cmf, xyz_);
  }
  return rec709_psf_from_xyz(xyz_, degrees_per_pixel(), "glare/cpu_float_chromatic_psf");
}

}  // namespace glarelab
