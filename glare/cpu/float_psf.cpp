#include "glare/cpu/float_psf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "glare/cpu/psf.h"

namespace glarelab {
namespace {

const CpuFloatPsfSettings& checked(const CpuFloatPsfSettings& settings) {
  const int n = settings.raster.grid_px;
  if (n < 2 || n % 2 != 0) throw std::invalid_argument("glare/cpu/float_psf: grid size must be even and >= 2");
  if (!(settings.wavelength_nm > 0.0)) throw std::invalid_argument("glare/cpu/float_psf: wavelength must be > 0 nm");
  return settings;
}

}  // namespace

CpuFloatPsf::CpuFloatPsf(const CpuFloatPsfSettings& settings)
    : settings_(checked(settings)), spectrum_(settings.raster.grid_px, settings.threads) {
  settings_.raster.threads = settings.threads;
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
  if (grid_.grid_px != settings_.raster.grid_px) throw std::logic_error("glare/cpu/float_psf: transform before rasterise");
  spectrum_.transform(grid_, settings_.phase, pupil_diameter_mm, error, wavelength_nm);  // it checks the wavelength
}

Psf CpuFloatPsf::monochromatic_psf() const {
  const int n = settings_.raster.grid_px;
  const std::size_t count = static_cast<std::size_t>(n) * n;
  double sum = 0.0;
  const float* power = power_column_major();
  for (std::size_t k = 0; k < count; ++k) sum += power[k];
  Psf psf;
  psf.size_px = n;
  psf.channels = 1;
  psf.degrees_per_pixel = degrees_per_pixel();
  psf.values.resize(count);
  for (int x = 0; x < n; ++x)
    for (int y = 0; y < n; ++y) psf.at(0, x, y) = power[static_cast<std::size_t>(x) * n + y] / sum;
  return psf;
}

}  // namespace glarelab
