#include "glare/refraction/astigmatic_phase.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace glarelab {

double power_error_phase_rad(const DioptricPower& error, double wavelength_nm, double x_m, double y_m) {
  const double wavelength_m = wavelength_nm * 1e-9;
  return std::numbers::pi / wavelength_m * (error.xx() * x_m * x_m + 2.0 * error.xy() * x_m * y_m + error.yy() * y_m * y_m);
}

std::vector<std::complex<double>> apply_power_error_phase(const ApertureGrid& grid, const DioptricPower& error,
                                                          double wavelength_nm) {
  const int n = grid.grid_px;
  const double dx_m = grid.pixel_mm() * 1e-3;
  std::vector<std::complex<double>> field(grid.transmittance.size());
  for (int j = 0; j < n; ++j) {
    const double y_m = (n / 2 - j) * dx_m;
    for (int i = 0; i < n; ++i) {
      const double x_m = (i - n / 2) * dx_m;
      const std::size_t index = static_cast<std::size_t>(j) * n + i;
      const double a = grid.transmittance[index];
      field[index] = a == 0.0 ? std::complex<double>(0.0, 0.0)
                              : std::polar(a, power_error_phase_rad(error, wavelength_nm, x_m, y_m));
    }
  }
  return field;
}

PhaseSamplingReport check_power_error_sampling(const DioptricPower& error, double wavelength_nm, double pupil_radius_mm,
                                               double pixel_mm, double aperture_width_mm) {
  const PrincipalPowers principal = principal_powers(error);
  const double largest_dioptres = std::max(std::abs(principal.p1_dioptres), std::abs(principal.p2_dioptres));
  return check_phase_sampling(largest_dioptres / (wavelength_nm * 1e-9), pupil_radius_mm, pixel_mm, aperture_width_mm);
}

}  // namespace glarelab
