#include "glare/cpu/float_psf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/parallel_for.h"
#include "glare/refraction/astigmatic_phase.h"
#include "glare/cpu/complex_transpose.h"
#include "glare/cpu/psf.h"

namespace glarelab {

CpuFloatPsf::CpuFloatPsf(const CpuFloatPsfSettings& settings) : settings_(settings) {
  settings_.raster.threads = settings.threads;
  const int n = settings_.raster.grid_px;
  if (n < 2 || n % 2 != 0) throw std::invalid_argument("glare/cpu/float_psf: grid size must be even and >= 2");
  if (!(settings.wavelength_nm > 0.0)) throw std::invalid_argument("glare/cpu/float_psf: wavelength must be > 0 nm");
  const std::size_t count = static_cast<std::size_t>(n) * n;
  field_ = FftwFloatBuffer<std::complex<float>>(count);
  columns_ = FftwFloatBuffer<std::complex<float>>(count);
  spectrum_ = FftwFloatBuffer<std::complex<float>>(count);
  row_tiles_ = FftwFloatBuffer<std::complex<float>>(static_cast<std::size_t>(std::max(1, settings.threads)) * kRowTile * n);
  power_ = FftwFloatBuffer<float>(count);
  row_fft_ = FftwFloatPlan::complex_row_forward(n, field_.data(), spectrum_.data());
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
    throw std::invalid_argument("glare/cpu/float_psf: wavelength must be > 0 nm");
  const int n = settings_.raster.grid_px;
  if (grid_.grid_px != n) throw std::logic_error("glare/cpu/float_psf: transform before rasterise");
  // A spherical error is glare/wave/fresnel.h's quadratic phase pi c r^2 of its one power, computed as it was
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
  // Only the rows that can meet the pupil (|row - N/2| <= r / dx + 1/2, glare/eye/aperture_raster.h) are
  // written; rows the last frame wrote outside them are cleared, the rest of the field stays 0.
  const double dx_m = grid_.pixel_mm() * 1e-3;
  const int reach = static_cast<int>(std::ceil(0.5 * pupil_diameter_mm / grid_.pixel_mm())) + 1;
  const int first_row = std::max(0, n / 2 - reach), last_row = std::min(n - 1, n / 2 + reach);
  for (int j = written_first_row_; j <= written_last_row_; ++j)
    if (j < first_row || j > last_row)
      std::fill(&field_[static_cast<std::size_t>(j) * n], &field_[static_cast<std::size_t>(j) * n] + n, std::complex<float>{});
  // The same rows' entries in columns_: the runs [written_first_row_, first_row) and
  // (last_row, written_last_row_] of each of its rows.
  const int stale_above = std::max(0, std::min(first_row, written_last_row_ + 1) - written_first_row_);
  const int stale_below_first = std::max(last_row + 1, written_first_row_);
  const int stale_below = std::max(0, written_last_row_ + 1 - stale_below_first);
  if (stale_above > 0 || stale_below > 0)
    parallel_chunks(n, settings_.threads, [&](int first, int last) {
      for (int u = first; u < last; ++u) {
        std::complex<float>* column = &columns_[static_cast<std::size_t>(u) * n];
        std::fill_n(column + written_first_row_, stale_above, std::complex<float>{});
        std::fill_n(column + stale_below_first, stale_below, std::complex<float>{});
      }
    });
  written_first_row_ = first_row;
  written_last_row_ = last_row;
  // The spherical phase pi c (x^2 + y^2) is a sum of an x and a y term, so exp(i phi) is the product
  // of a factor per column and one per row: a table of the pupil's N or fewer values (x and y take the
  // same offsets from N/2) instead of a sine and a cosine per pixel. The product differs from
  // apply_quadratic_phase's polar(a, pi c r^2) by a few roundings in double, far below the float
  // the value is rounded to (the field came out the same bits at N = 256 to 1024 for the eye model).
  const bool separable = !astigmatic && coefficient != 0.0;
  if (separable) {
    phase_factor_.resize(static_cast<std::size_t>(n));
    for (int i = first_row; i <= last_row; ++i) {
      const double x_m = (i - n / 2) * dx_m;
      phase_factor_[static_cast<std::size_t>(i)] = std::polar(1.0, quadratic_phase_rad(coefficient, x_m * x_m));
    }
  }
  row_energy_.assign(static_cast<std::size_t>(n), 0.0);  // per row: the sum does not depend on the threads
  const int row_count = last_row - first_row + 1;
  const int tile_count = (row_count + kRowTile - 1) / kRowTile;
  // The tiles shared among the threads, each thread with a tile buffer of its own.
  parallel_indexed_chunks(tile_count, settings_.threads, [&](int chunk, int first_tile, int last_tile) {
    std::complex<float>* tile = &row_tiles_[static_cast<std::size_t>(chunk) * kRowTile * n];
    for (int t = first_tile; t < last_tile; ++t) {
      const int tile_first = first_row + t * kRowTile, tile_rows = std::min(kRowTile, last_row + 1 - tile_first);
      for (int r = 0; r < tile_rows; ++r) {
        const int j = tile_first + r;
        double sum = 0.0;
        const double y_m = (n / 2 - j) * dx_m;
        const std::complex<double> y_factor =
            separable ? phase_factor_[static_cast<std::size_t>(j)] : std::complex<double>{};
        // The pupil's columns are the range of its rows (the pupil is centred, the aperture 0
        // outside its bounding square): the rest of the row is 0, written as a block (the
        // per-pixel loop over the whole row was most of the row pass at N = 512).
        const int first_column = first_row, last_column = last_row;
        std::complex<float>* field_row = &field_[static_cast<std::size_t>(j) * n];
        std::fill(field_row, field_row + first_column, std::complex<float>{});
        std::fill(field_row + last_column + 1, field_row + n, std::complex<float>{});
        for (int i = first_column; i <= last_column; ++i) {
          const std::size_t index = static_cast<std::size_t>(j) * n + i;
          const double a = grid_.transmittance[index];
          std::complex<double> value{a, 0.0};
          if (astigmatic && a != 0.0) {
            const double x_m = (i - n / 2) * dx_m;
            value = std::polar(a, power_error_phase_rad(error, wavelength_nm, x_m, y_m));
          } else if (separable && a != 0.0) {
            // Written out: std::complex's operator* checks for NaN (C99 Annex G).
            const std::complex<double> x_factor = phase_factor_[static_cast<std::size_t>(i)];
            value = {a * (x_factor.real() * y_factor.real() - x_factor.imag() * y_factor.imag()),
                     a * (x_factor.real() * y_factor.imag() + x_factor.imag() * y_factor.real())};
          }
          sum += a * a;
          field_[index] = {static_cast<float>(value.real()), static_cast<float>(value.imag())};
        }
        row_energy_[static_cast<std::size_t>(j)] = sum;
        // The row's DFT while the row is in cache: the first pass of the 2D FFT.
        row_fft_.execute(&field_[static_cast<std::size_t>(j) * n], tile + static_cast<std::size_t>(r) * n);
      }
      // The tile transposed: its rows' values at frequency u are one run of columns_'s row u.
      const auto stride = static_cast<std::size_t>(n);
      transpose_complex(tile, stride, tile_rows, stride, &columns_[static_cast<std::size_t>(tile_first)], stride);
    }
  });
  double aperture_energy = 0.0;
  for (double e : row_energy_) aperture_energy += e;
  if (!(aperture_energy > 0.0))
    throw ClosedApertureError("glare/cpu/float_psf: the aperture transmits no light (pupil outside the grid or fully blocked)");

  // The second pass: every row of columns_ (a column of the row transforms) into spectrum_.
  parallel_chunks(n, settings_.threads, [&](int first, int last) {
    for (int u = first; u < last; ++u)
      row_fft_.execute(&columns_[static_cast<std::size_t>(u) * n], &spectrum_[static_cast<std::size_t>(u) * n]);
  });
  // |F|^2 with the fftshift, column-major: pixel (x, y) takes frequency (u, v) = ((x + N/2) mod N,
  // (y + N/2) mod N), that is spectrum_[u][v], so PSF column x is spectrum_ row u with its halves
  // swapped: read and written in order. (Row-major, each output value came from another spectrum_
  // row, 8 KB apart at N = 1024: that pass took 1.6 of the transform's 3.6 ms there.)
  const int half = n / 2;
  parallel_chunks(n, settings_.threads, [&](int first, int last) {
    for (int x = first; x < last; ++x) {
      const int u = x + half < n ? x + half : x + half - n;
      const std::complex<float>* source = &spectrum_[static_cast<std::size_t>(u) * n];
      float* target = &power_[static_cast<std::size_t>(x) * n];
      for (int y = 0; y < half; ++y) target[y] = std::norm(source[y + half]);
      for (int y = half; y < n; ++y) target[y] = std::norm(source[y - half]);
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
  for (int x = 0; x < n; ++x)
    for (int y = 0; y < n; ++y) psf.at(0, x, y) = power_[static_cast<std::size_t>(x) * n + y] / sum;
  return psf;
}

}  // namespace glarelab
