#include "glare/wave/chromatic_psf.h"

#include <sstream>
#include <stdexcept>
#include <string>

#include "glare/refraction/astigmatic_phase.h"
#include "glare/refraction/chromatic_eye.h"
#include "glare/wave/cie_cmf.h"
#include "glare/cpu/psf.h"

namespace glarelab {

DioptricPower chromatic_power_error(const DioptricPower& reference_error, double wavelength_nm,
                                    const ChromaticPsfOptions& options) {
  if (!options.longitudinal_chromatic_aberration) return reference_error;
  return reference_error +
         DioptricPower::spherical(chromatic_power_excess_dioptres(wavelength_nm, options.reference_wavelength_nm));
}

ChromaticPsfResult compute_chromatic_psf(const ApertureGeometry& geometry, const ChromaticPsfOptions& options) {
  if (options.wavelength_samples < 1) throw std::invalid_argument("glare/wave/chromatic_psf: need at least one wavelength sample");
  if (!(options.reference_wavelength_nm > 0.0))
    throw std::invalid_argument("glare/wave/chromatic_psf: the reference wavelength must be > 0 nm");
  const ApertureGrid grid = rasterise_aperture(geometry, options.raster);
  const DioptricPower reference_error = geometry.total_power_error();
  MonochromaticPsfOptions mono;
  mono.raster = options.raster;
  mono.phase = PhaseForm::defocus;
  mono.strict_sampling = options.strict_sampling;
  mono.precision = options.precision;

  ChromaticPsfResult result;
  XyzPlanes xyz(grid.grid_px);
  double worst_step_rad = 0.0;
  for (const SpectralSample& sample : spectral_samples(options.wavelength_samples)) {
    mono.wavelength_nm = sample.wavelength_nm;
    const DioptricPower error = chromatic_power_error(reference_error, sample.wavelength_nm, options);
    const MonochromaticPsfResult psf = compute_monochromatic_psf(grid, geometry.pupil_diameter_mm, error, mono);
    if (!psf.sampling_warning.empty()) {
      ++result.aliased_wavelengths;
      const double step_rad = check_power_error_sampling(error, sample.wavelength_nm, 0.5 * geometry.pupil_diameter_mm,
                                                         grid.pixel_mm(), grid.aperture_width_mm)
                                  .max_phase_step_rad;
      if (step_rad > worst_step_rad) {
        worst_step_rad = step_rad;
        std::ostringstream where;
        where << " (at " << sample.wavelength_nm << " nm)";
        result.sampling_warning = psf.sampling_warning + where.str();
      }
    }
    // PSF_lambda has pixels of lambda / W: reference pixel x lies at its pixel x lambda_ref / lambda.
    accumulate_resampled_psf(psf.psf, options.reference_wavelength_nm / sample.wavelength_nm,
                             cie1931_cmf(sample.wavelength_nm), xyz);
  }
  result.spectral = rec709_psf_from_xyz(
      xyz, psf_degrees_per_pixel(options.reference_wavelength_nm, grid.aperture_width_mm), "glare/wave/chromatic_psf");
  return result;
}

}  // namespace glarelab
