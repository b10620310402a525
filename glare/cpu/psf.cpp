#include "glare/cpu/psf.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "glare/refraction/astigmatic_phase.h"

namespace glarelab {

double psf_degrees_per_pixel(double wavelength_nm, double aperture_width_mm) {
  // Eq. 3 evaluates the FT at p = x_i / (lambda d); the DFT's frequency step is 1 / (N dx), so one
  // PSF pixel is lambda d / (N dx) on the retina, an angle of lambda / (N dx) radians seen from the pupil.
  const double radians = (wavelength_nm * 1e-9) / (aperture_width_mm * 1e-3);
  return radians * 180.0 / std::numbers::pi;
}

double airy_core_diameter_px(double pupil_diameter_mm, double aperture_width_mm) {
  return 2.44 * aperture_width_mm / pupil_diameter_mm;
}

std::vector<double> shifted_power_spectrum(std::vector<std::complex<double>> field, int grid_px, FftPrecision precision) {
  const int n = grid_px;
  const std::size_t count = static_cast<std::size_t>(n) * n;
  if (field.size() != count) throw std::invalid_argument("glare/cpu/psf: field is not N x N");
  std::vector<double> power(count);
  auto store = [&](int u, int v, double value) {
    // fftshift: frequency index (u, v) goes to pixel ((u + N/2) mod N, (v + N/2) mod N).
    const int x = (u + n / 2) % n;
    const int y = (v + n / 2) % n;
    power[static_cast<std::size_t>(y) * n + x] = value;
  };
  if (precision == FftPrecision::float64) {
    fft2d_forward(field, n, n);
    for (int v = 0; v < n; ++v)
      for (int u = 0; u < n; ++u) store(u, v, std::norm(field[static_cast<std::size_t>(v) * n + u]));
  } else {
    std::vector<std::complex<float>> single(count);
    for (std::size_t k = 0; k < count; ++k)
      single[k] = {static_cast<float>(field[k].real()), static_cast<float>(field[k].imag())};
    field.clear();
    fft2d_forward(single, n, n);
    for (int v = 0; v < n; ++v)
      for (int u = 0; u < n; ++u) {
        const std::complex<float> c = single[static_cast<std::size_t>(v) * n + u];
        store(u, v, static_cast<double>(c.real()) * c.real() + static_cast<double>(c.imag()) * c.imag());
      }
  }
  return power;
}

namespace {

bool spherical(const DioptricPower& power) { return power.xy() == 0.0 && power.xx() == power.yy(); }

void record_sampling(const PhaseSamplingReport& sampling, const MonochromaticPsfOptions& options,
                     MonochromaticPsfResult& result) {
  if (!sampling.aliased) return;
  if (options.strict_sampling) throw std::runtime_error(sampling.warning);
  result.sampling_warning = sampling.warning;
}

// |FFT(field)|^2 normalised to sum 1 (Ritschel et al. 2009, Eq. 3), on the grid's angular pixels.
void finish_psf(const ApertureGrid& grid, std::vector<std::complex<double>> field, const MonochromaticPsfOptions& options,
                MonochromaticPsfResult& result) {
  const int n = grid.grid_px;
  std::vector<double> power = shifted_power_spectrum(std::move(field), n, options.precision);
  for (double p : power) result.unnormalised_sum += p;
  // K: Ritschel's 1 / (lambda d)^2 makes the retinal irradiance physical; for a PSF the constant
  // that matters is the one that makes it sum to 1.
  const double k = 1.0 / result.unnormalised_sum;
  for (double& p : power) p *= k;

  result.psf.size_px = n;
  result.psf.channels = 1;
  result.psf.degrees_per_pixel = psf_degrees_per_pixel(options.wavelength_nm, grid.aperture_width_mm);
  result.psf.values = std::move(power);
}

void measure_aperture(const ApertureGrid& grid, MonochromaticPsfResult& result) {
  for (double a : grid.transmittance) result.aperture_energy += a * a;
  if (!(result.aperture_energy > 0.0))
    throw ClosedApertureError("glare/cpu/psf: the aperture transmits no light (pupil outside the grid or fully blocked)");
}

}  // namespace

MonochromaticPsfResult compute_monochromatic_psf(const ApertureGeometry& geometry, const MonochromaticPsfOptions& options) {
  const ApertureGrid grid = rasterise_aperture(geometry, options.raster);
  const DioptricPower& refraction = geometry.refraction_error;
  if (refraction.xx() == 0.0 && refraction.yy() == 0.0 && refraction.xy() == 0.0)
    return compute_monochromatic_psf(grid, geometry.pupil_diameter_mm, geometry.defocus_dioptres, options);
  return compute_monochromatic_psf(grid, geometry.pupil_diameter_mm, geometry.total_power_error(), options);
}

MonochromaticPsfResult compute_monochromatic_psf(const ApertureGrid& grid, double pupil_diameter_mm,
                                                 double defocus_dioptres, const MonochromaticPsfOptions& options) {
  if (!(options.wavelength_nm > 0.0)) throw std::invalid_argument("glare/cpu/psf: wavelength must be > 0 nm");
  MonochromaticPsfResult result;
  const double coefficient = phase_coefficient_per_m2(options.phase, options.wavelength_nm, defocus_dioptres);
  record_sampling(check_phase_sampling(coefficient, 0.5 * pupil_diameter_mm, grid.pixel_mm(), grid.aperture_width_mm),
                  options, result);
  measure_aperture(grid, result);
  finish_psf(grid, apply_quadratic_phase(grid, coefficient), options, result);
  return result;
}

MonochromaticPsfResult compute_monochromatic_psf(const ApertureGrid& grid, double pupil_diameter_mm,
                                                 const DioptricPower& power_error, const MonochromaticPsfOptions& options) {
  if (options.phase != PhaseForm::defocus)
    throw std::invalid_argument(std::string("glare/cpu/psf: a sphero-cylindrical power error needs the defocus phase, not '") +
                                phase_form_name(options.phase) + "'");
  if (spherical(power_error)) return compute_monochromatic_psf(grid, pupil_diameter_mm, power_error.xx(), options);
  if (!(options.wavelength_nm > 0.0)) throw std::invalid_argument("glare/cpu/psf: wavelength must be > 0 nm");
  MonochromaticPsfResult result;
  record_sampling(check_power_error_sampling(power_error, options.wavelength_nm, 0.5 * pupil_diameter_mm, grid.pixel_mm(),
                                             grid.aperture_width_mm),
                  options, result);
  measure_aperture(grid, result);
  finish_psf(grid, apply_power_error_phase(grid, power_error, options.wavelength_nm), options, result);
  return result;
}

}  // namespace glarelab
