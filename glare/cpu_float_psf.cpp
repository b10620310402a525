#include "glare/cpu_float_psf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "glare/astigmatic_phase.h"
#include "glare/parallel_rows.h"
#include "glare/psf_cpu.h"

namespace glarelab {

CpuFloatPsf::CpuFloatPsf(const CpuFloatPsfSettings& settings) : settings_(settings) {
  settings_.raster.threads = settings.threads;
  const int n = settings_.raster.grid_px;
  if (n < 2 || n % 2 != 0) throw std::invalid_argument("glare/cpu_float_psf: grid size must be even and >= 2");
  if (!(settings.wavelength_nm > 0.0)) throw std::invalid_argument("glare/cpu_float_psf: wavelength must be > 0 nm");
  const std::size_t count = static_cast<std::size_t>(n) * n;
  field_ = FftwFloatBuffer<std::complex<float>>(count);
  spectrum_ = FftwFloatBuffer<std::complex<float>>(count);
  power_ = FftwFloatBuffer<float>(count);
  fft_ = FftwFloatPlan::complex_forward(n, n, field_.data(), spectrum_.data(), settings.threads);
}

double CpuFloatPsf::degrees_per_pixel() const {
  return psf_degrees_per_pixel(settings_.wavelength_nm, settings_.raster.aperture_width_mm);
}

void CpuFloatPsf::rasterise(const ApertureGeometry& geometry) { rasterise_aperture(geometry, settings_.raster, grid_); }

void CpuFloatPsf::transform(double pupil_diameter_mm, double defocus_dioptres) {
  transform(pupil_diameter_mm, DioptricPower::spherical(defocus_dioptres));
}

void CpuFloatPsf::transform(double pupil_diameter_mm, const DioptricPower& error) {
  transform(pupil_diameter_mm, error, settings_.wavelength_nm);
}

void CpuFloatPsf::transform(double pupil_diameter_mm, const DioptricPower& error, double wavelength_nm) {
  if (!(wavelength_nm > 0.0) || !std::isfinite(wavelength_nm))
    throw std::invalid_argument("glare/cpu_float_psf: wavelength must be > 0 nm");
  const int n = settings_.raster.grid_px;
  if (grid_.grid_px != n) throw std::logic_error("glare/cpu_float_psf: transform before rasterise");
  // A spherical error is fresnel.h's quadratic phase pi c r^2 of its one power, computed as it was
  // before errors had a cylinder; only an astigmatic one takes the general form.
  const bool astigmatic = settings_.phase == PhaseForm::defocus && (error.xy() != 0.0 || error.xx() != error.yy());
  const double coefficient = phase_coefficient_per_m2(settings_.phase, wavelength_nm, error.xx());
  const PhaseSamplingReport sampling =
      astigmatic ? check_power_error_sampling(error, wavelength_nm, 0.5 * pupil_diameter_mm, grid_.pixel_mm(),
                                              grid_.aperture_width_mm)
                 : check_phase_sampling(coefficient, 0.5 * pupil_diameter_mm, grid_.pixel_mm(), grid_.aperture_width_mm);
  sampling_warning_ = sampling.aliased ? sampling.warning : std::string();

  // A exp(i phi) at pixel centres, as apply_quadratic_phase (spherical) or apply_power_error_phase
  // (astigmatic) computes it in double, rounded to float.
  // Only the rows that can meet the pupil (|row - N/2| <= r / dx + 1/2, aperture_raster.h) are
  // written; rows the last frame wrote outside them are cleared, the rest of the field stays 0.
  const double dx_m = grid_.pixel_mm() * 1e-3;
  const int reach = static_cast<int>(std::ceil(0.5 * pupil_diameter_mm / grid_.pixel_mm())) + 1;
  const int first_row = std::max(0, n / 2 - reach), last_row = std::min(n - 1, n / 2 + reach);
  for (int j = written_first_row_; j <= written_last_row_; ++j)
    if (j < first_row || j > last_row)
      std::fill(&field_[static_cast<std::size_t>(j) * n], &field_[static_cast<std::size_t>(j) * n] + n, std::complex<float>{});
  written_first_row_ = first_row;
  written_last_row_ = last_row;
  row_energy_.assign(static_cast<std::size_t>(n), 0.0);  // per row: the sum does not depend on the threads
  parallel_chunks(last_row - first_row + 1, settings_.threads, [&](int first, int last) {
    for (int j = first_row + first; j < first_row + last; ++j) {
      double sum = 0.0;
      const double y_m = (n / 2 - j) * dx_m;
      for (int i = 0; i < n; ++i) {
        const std::size_t index = static_cast<std::size_t>(j) * n + i;
        const double a = grid_.transmittance[index];
        std::complex<double> value{a, 0.0};
        if (astigmatic && a != 0.0) {
          const double x_m = (i - n / 2) * dx_m;
          value = std::polar(a, power_error_phase_rad(error, wavelength_nm, x_m, y_m));
        } else if (coefficient != 0.0 && a != 0.0) {
          const double x_m = (i - n / 2) * dx_m;
          value = std::polar(a, quadratic_phase_rad(coefficient, x_m * x_m + y_m * y_m));
        }
        sum += a * a;
        field_[index] = {static_cast<float>(value.real()), static_cast<float>(value.imag())};
      }
      row_energy_[static_cast<std::size_t>(j)] = sum;
    }
  });
  double aperture_energy = 0.0;
  for (double e : row_energy_) aperture_energy += e;
  if (!(aperture_energy > 0.0))
    throw ClosedApertureError("glare/cpu_float_psf: the aperture transmits no light (pupil outside the grid or fully blocked)");

  fft_.execute();
  // fftshift: frequency (u, v) goes to pixel ((u + N/2) mod N, (v + N/2) mod N), row by row in halves.
  parallel_chunks(n, settings_.threads, [&](int first, int last) {
    for (int y = first; y < last; ++y) {
      const std::complex<float>* source = &spectrum_[static_cast<std::size_t>((y + n / 2) % n) * n];
      float* target = &power_[static_cast<std::size_t>(y) * n];
      for (int x = 0; x < n; ++x) {
        const std::complex<float> c = source[(x + n / 2) % n];
        target[x] = c.real() * c.real() + c.imag() * c.imag();
      }
    }
  });
}

Psf CpuFloatPsf::monochromatic_psf() const {
  const int n = settings_.raster.grid_px;
  const std::size_t count = static_cast<std::size_t>(n) * n;
  double sum = 0.0;
  for (std::size_t k = 0; k < count; ++k) sum += power_[k];
  Psf psf;
  psf.size_px = n;
  psf.channels = 1;
  psf.degrees_per_pixel = degrees_per_pixel();
  psf.values.resize(count);
  for (std::size_t k = 0; k < count; ++k) psf.values[k] = power_[k] / sum;
  return psf;
}

}  // namespace glarelab
