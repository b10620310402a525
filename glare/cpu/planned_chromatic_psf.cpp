#include "glare/cpu/planned_chromatic_psf.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/parallel_for.h"
#include "glare/refraction/astigmatic_phase.h"
#include "glare/refraction/chromatic_eye.h"
#include "glare/cpu/psf.h"

namespace glarelab {
namespace {

int checked_grid(const CpuPlannedChromaticSettings& settings) {
  if (settings.grid_px < 2 || settings.grid_px % 2 != 0)
    throw std::invalid_argument("glare/cpu/planned_chromatic_psf: grid size must be even and >= 2");
  if (settings.wavelength_samples < 1)
    throw std::invalid_argument("glare/cpu/planned_chromatic_psf: need at least one wavelength sample");
  if (!(settings.reference_wavelength_nm > 0.0))
    throw std::invalid_argument("glare/cpu/planned_chromatic_psf: the reference wavelength must be > 0 nm");
  return settings.grid_px;
}

}  // namespace

CpuPlannedChromaticPsf::CpuPlannedChromaticPsf(const CpuPlannedChromaticSettings& settings)
    : settings_(settings), spectrum_(checked_grid(settings), settings.threads), xyz_(settings.grid_px) {
  for (const SpectralSample& sample : spectral_samples(settings.wavelength_samples)) {
    Wavelength wavelength;
    wavelength.wavelength_nm = sample.wavelength_nm;
    // Throws (glare/refraction/chromatic_eye) for a reference at or below the fit's pole, before any transform.
    wavelength.excess_dioptres = chromatic_power_excess_dioptres(sample.wavelength_nm, settings.reference_wavelength_nm);
    wavelength.cmf = cie1931_cmf(sample.wavelength_nm);
    // glare/wave/spectral_accumulation.cpp: x_source = (x - c) lambda_ref / lambda + c, c = N/2.
    const int n = settings.grid_px;
    const double centre = n / 2;
    const double scale = settings.reference_wavelength_nm / sample.wavelength_nm;
    wavelength.first_px = n;
    for (int x = 0; x < n; ++x) {
      const double position = (x - centre) * scale + centre;
      const double floor_position = std::floor(position);
      const int x0 = static_cast<int>(floor_position);
      const double fraction = position - floor_position;
      const bool inside0 = x0 >= 0 && x0 < n, inside1 = x0 + 1 >= 0 && x0 + 1 < n;
      wavelength.index0.push_back(std::clamp(x0, 0, n - 1));
      wavelength.index1.push_back(std::clamp(x0 + 1, 0, n - 1));
      wavelength.weight0.push_back(inside0 ? 1.0 - fraction : 0.0);
      wavelength.weight1.push_back(inside1 ? fraction : 0.0);
      if (inside0 || inside1) {
        wavelength.first_px = std::min(wavelength.first_px, x);
        wavelength.last_px = std::max(wavelength.last_px, x);
      }
    }
    wavelengths_.push_back(std::move(wavelength));
  }
}

void CpuPlannedChromaticPsf::accumulate(const Wavelength& wavelength, const double* power, double scale) {
  const int n = settings_.grid_px;
  const std::size_t plane = static_cast<std::size_t>(n) * n;
  const int first = wavelength.first_px, count = wavelength.last_px - wavelength.first_px + 1;
  if (count <= 0) return;
  const double wx = scale * wavelength.cmf.x, wy = scale * wavelength.cmf.y, wz = scale * wavelength.cmf.z;
  // Output rows are independent: each chunk writes only its own rows, so the sums do not depend on
  // the thread count.
  parallel_chunks(count, settings_.threads, [&](int chunk_first, int chunk_last) {
    std::vector<double> h0(static_cast<std::size_t>(n)), h1(static_cast<std::size_t>(n));
    const int* index0 = wavelength.index0.data();
    const int* index1 = wavelength.index1.data();
    const double* weight0 = wavelength.weight0.data();
    const double* weight1 = wavelength.weight1.data();
    const auto interpolate_row = [&](int row, std::vector<double>& h) {
      const double* source = power + static_cast<std::size_t>(row) * n;
      for (int x = first; x < first + count; ++x) h[x] = weight0[x] * source[index0[x]] + weight1[x] * source[index1[x]];
    };
    for (int y = first + chunk_first; y < first + chunk_last; ++y) {
      const auto row = static_cast<std::size_t>(y);
      interpolate_row(wavelength.index0[row], h0);
      interpolate_row(wavelength.index1[row], h1);
      const double a = wavelength.weight0[row], b = wavelength.weight1[row];
      double* x_plane = &xyz_.values[row * n];
      double* y_plane = x_plane + plane;
      double* z_plane = y_plane + plane;
      for (int x = first; x < first + count; ++x) {
        const auto k = static_cast<std::size_t>(x);
        const double value = a * h0[k] + b * h1[k];
        x_plane[k] += wx * value;
        y_plane[k] += wy * value;
        z_plane[k] += wz * value;
      }
    }
  });
}

double CpuPlannedChromaticPsf::degrees_per_pixel() const {
  return psf_degrees_per_pixel(settings_.reference_wavelength_nm, settings_.aperture_width_mm);
}

SpectralPsfResult CpuPlannedChromaticPsf::compute(const CpuFloatPsf& psf, double pupil_diameter_mm,
                                                const DioptricPower& reference_error) {
  const int n = settings_.grid_px;
  if (psf.grid_px() != n || psf.aperture().aperture_width_mm != settings_.aperture_width_mm)
    throw std::invalid_argument("glare/cpu/planned_chromatic_psf: the CpuFloatPsf has another grid or has not rasterised an aperture");
  const std::size_t count = static_cast<std::size_t>(n) * n;
  std::fill(xyz_.values.begin(), xyz_.values.end(), 0.0);
  sampling_warning_.clear();
  aliased_wavelengths_ = 0;
  double worst_step_rad = 0.0;
  for (const Wavelength& wavelength : wavelengths_) {
    // glare/wave/chromatic_psf.cpp's chromatic_power_error: E_ref + [LCA(lambda) - LCA(lambda_ref)] I.
    const DioptricPower error = reference_error + DioptricPower::spherical(wavelength.excess_dioptres);
    spectrum_.transform(psf.aperture(), psf.phase(), pupil_diameter_mm, error, wavelength.wavelength_nm);
    if (!spectrum_.sampling_warning().empty()) {
      ++aliased_wavelengths_;
      const double step_rad = check_power_error_sampling(error, wavelength.wavelength_nm, 0.5 * pupil_diameter_mm,
                                                         psf.aperture().pixel_mm(), psf.aperture().aperture_width_mm)
                                  .max_phase_step_rad;
      if (step_rad > worst_step_rad) {
        worst_step_rad = step_rad;
        std::ostringstream where;
        where << " (at " << wavelength.wavelength_nm << " nm)";
        sampling_warning_ = spectrum_.sampling_warning() + where.str();
      }
    }
    // The unit-sum PSF of glare/cpu/psf.h (K = 1 / sum), as the reference accumulates it, with the
    // Jacobian (lambda_ref / lambda)^2: a PSF at lambda has pixels of lambda / W, the reference
    // grid pixels of lambda_ref / W.
    const double* power = spectrum_.power_column_major();
    double sum = 0.0;
    for (std::size_t k = 0; k < count; ++k) sum += power[k];
    const double ratio = settings_.reference_wavelength_nm / wavelength.wavelength_nm;
    accumulate(wavelength, power, ratio * ratio / sum);
  }
  // The power was column-major, and so are the sums (accumulate treats both axes alike): each plane
  // transposed back to the row-major layout of glare/wave/spectral_accumulation.h.
  for (std::size_t c = 0; c < 3; ++c) {
    double* values = &xyz_.values[c * count];
    for (int x = 0; x < n; ++x)
      for (int y = x + 1; y < n; ++y)
        std::swap(values[static_cast<std::size_t>(x) * n + y], values[static_cast<std::size_t>(y) * n + x]);
  }
  return rec709_psf_from_xyz(xyz_, degrees_per_pixel(), "glare/cpu/planned_chromatic_psf");
}

}  // namespace glarelab
