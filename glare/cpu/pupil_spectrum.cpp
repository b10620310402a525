#include "glare/cpu/pupil_spectrum.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/parallel_for.h"
#include "glare/cpu/complex_transpose.h"
#include "glare/refraction/astigmatic_phase.h"
#include "glare/wave/psf.h"

namespace glarelab {
namespace {

int checked_grid(int grid_px) {
  if (grid_px < 2 || grid_px % 2 != 0) throw std::invalid_argument("glare/cpu/pupil_spectrum: grid size must be even and >= 2");
  return grid_px;
}

}  // namespace

template <typename Real>
PupilSpectrum<Real>::PupilSpectrum(int grid_px, int threads) : grid_px_(checked_grid(grid_px)), threads_(std::max(1, threads)) {
  const std::size_t count = static_cast<std::size_t>(grid_px) * grid_px;
  field_ = FftwFloatBuffer<std::complex<Real>>(count);
  columns_ = FftwFloatBuffer<std::complex<Real>>(count);
  spectrum_ = FftwFloatBuffer<std::complex<Real>>(count);
  row_tiles_ = FftwFloatBuffer<std::complex<Real>>(static_cast<std::size_t>(threads_) * kRowTile * grid_px);
  power_ = FftwFloatBuffer<Real>(count);
  row_fft_ = RowPlan::complex_row_forward(grid_px, field_.data(), spectrum_.data());
}

template <typename Real>
void PupilSpectrum<Real>::clear_stale_rows(int first_row, int last_row) {
  const int n = grid_px_;
  for (int j = written_first_row_; j <= written_last_row_; ++j)
    if (j < first_row || j > last_row)
      std::fill(&field_[static_cast<std::size_t>(j) * n], &field_[static_cast<std::size_t>(j) * n] + n, std::complex<Real>{});
  // The same rows' entries in columns_: the runs [written_first_row_, first_row) and
  // (last_row, written_last_row_] of each of its rows.
  const int stale_above = std::max(0, std::min(first_row, written_last_row_ + 1) - written_first_row_);
  const int stale_below_first = std::max(last_row + 1, written_first_row_);
  const int stale_below = std::max(0, written_last_row_ + 1 - stale_below_first);
  if (stale_above > 0 || stale_below > 0)
    parallel_chunks(n, threads_, [&](int first, int last) {
      for (int u = first; u < last; ++u) {
        std::complex<Real>* column = &columns_[static_cast<std::size_t>(u) * n];
        std::fill_n(column + written_first_row_, stale_above, std::complex<Real>{});
        std::fill_n(column + stale_below_first, stale_below, std::complex<Real>{});
      }
    });
  written_first_row_ = first_row;
  written_last_row_ = last_row;
}

template <typename Real>
double PupilSpectrum<Real>::transform_pupil_rows(const ApertureGrid& grid, const PupilPhase& phase, int first_row,
                                                 int last_row) {
  const int n = grid_px_;
  const bool astigmatic = phase.astigmatic;
  const double coefficient = phase.coefficient;
  const double dx_m = grid.pixel_mm() * 1e-3;
  // The spherical phase pi c (x^2 + y^2) is a sum of an x and a y term, so exp(i phi) is the product
  // of a factor per column and one per row: a table of the pupil's N or fewer values (x and y take the
  // same offsets from N/2) instead of a sine and a cosine per pixel. The product differs from
  // apply_quadratic_phase's polar(a, pi c r^2) by a few roundings in double, far below the float
  // the float32 form rounds it to (its field came out the same bits at N = 256 to 1024 for the eye model).
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
  parallel_indexed_chunks(tile_count, threads_, [&](int chunk, int first_tile, int last_tile) {
    std::complex<Real>* tile = &row_tiles_[static_cast<std::size_t>(chunk) * kRowTile * n];
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
        std::complex<Real>* field_row = &field_[static_cast<std::size_t>(j) * n];
        std::fill(field_row, field_row + first_column, std::complex<Real>{});
        std::fill(field_row + last_column + 1, field_row + n, std::complex<Real>{});
        for (int i = first_column; i <= last_column; ++i) {
          const std::size_t index = static_cast<std::size_t>(j) * n + i;
          const double a = grid.transmittance[index];
          std::complex<double> value{a, 0.0};
          if (astigmatic && a != 0.0) {
            const double x_m = (i - n / 2) * dx_m;
            value = std::polar(a, power_error_phase_rad(phase.error, phase.wavelength_nm, x_m, y_m));
          } else if (separable && a != 0.0) {
            // Written out: std::complex's operator* checks for NaN (C99 Annex G).
            const std::complex<double> x_factor = phase_factor_[static_cast<std::size_t>(i)];
            value = {a * (x_factor.real() * y_factor.real() - x_factor.imag() * y_factor.imag()),
                     a * (x_factor.real() * y_factor.imag() + x_factor.imag() * y_factor.real())};
          }
          sum += a * a;
          field_[index] = {static_cast<Real>(value.real()), static_cast<Real>(value.imag())};
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
  return aperture_energy;
}

template <typename Real>
void PupilSpectrum<Real>::transform(const ApertureGrid& grid, PhaseForm phase, double pupil_diameter_mm,
                                    const DioptricPower& error, double wavelength_nm) {
  if (!(wavelength_nm > 0.0) || !std::isfinite(wavelength_nm))
    throw std::invalid_argument("glare/cpu/pupil_spectrum: wavelength must be > 0 nm");
  const int n = grid_px_;
  if (grid.grid_px != n) throw std::logic_error("glare/cpu/pupil_spectrum: the aperture is rasterised on another grid");
  // A spherical error is glare/wave/fresnel.h's quadratic phase pi c r^2 of its one power, computed as it
  // was before errors had a cylinder; only an astigmatic one takes the general form.
  const bool astigmatic = phase == PhaseForm::defocus && (error.xy() != 0.0 || error.xx() != error.yy());
  const double coefficient = phase_coefficient_per_m2(phase, wavelength_nm, error.xx());
  const PhaseSamplingReport sampling =
      astigmatic ? check_power_error_sampling(error, wavelength_nm, 0.5 * pupil_diameter_mm, grid.pixel_mm(),
                                              grid.aperture_width_mm)
                 : check_phase_sampling(coefficient, 0.5 * pupil_diameter_mm, grid.pixel_mm(), grid.aperture_width_mm);
  sampling_warning_ = sampling.aliased ? sampling.warning : std::string();

  // A exp(i phi) at pixel centres, as apply_quadratic_phase (spherical) or apply_power_error_phase
  // (astigmatic) computes it in double, rounded to Real. Only the rows that can meet the pupil
  // (|row - N/2| <= r / dx + 1/2, glare/eye/aperture_raster.h) are written; rows the last transform
  // wrote outside them are cleared, the rest of the field stays 0.
  const int reach = static_cast<int>(std::ceil(0.5 * pupil_diameter_mm / grid.pixel_mm())) + 1;
  const int first_row = std::max(0, n / 2 - reach), last_row = std::min(n - 1, n / 2 + reach);
  clear_stale_rows(first_row, last_row);
  if (!(transform_pupil_rows(grid, PupilPhase{error, wavelength_nm, astigmatic, coefficient}, first_row, last_row) > 0.0))
    throw ClosedApertureError("glare/cpu/pupil_spectrum: the aperture transmits no light (pupil outside the grid or fully blocked)");

  // The second pass: every row of columns_ (a column of the row transforms) into spectrum_.
  parallel_chunks(n, threads_, [&](int first, int last) {
    for (int u = first; u < last; ++u)
      row_fft_.execute(&columns_[static_cast<std::size_t>(u) * n], &spectrum_[static_cast<std::size_t>(u) * n]);
  });
  // |F|^2 with the fftshift, column-major: pixel (x, y) takes frequency (u, v) = ((x + N/2) mod N,
  // (y + N/2) mod N), that is spectrum_[u][v], so PSF column x is spectrum_ row u with its halves
  // swapped: read and written in order. (Row-major, each output value came from another spectrum_
  // row, 8 KB apart at N = 1024: that pass took 1.6 of the transform's 3.6 ms there.)
  const int half = n / 2;
  parallel_chunks(n, threads_, [&](int first, int last) {
    for (int x = first; x < last; ++x) {
      const int u = x + half < n ? x + half : x + half - n;
      const std::complex<Real>* source = &spectrum_[static_cast<std::size_t>(u) * n];
      Real* target = &power_[static_cast<std::size_t>(x) * n];
      for (int y = 0; y < half; ++y) target[y] = std::norm(source[y + half]);
      for (int y = half; y < n; ++y) target[y] = std::norm(source[y - half]);
    }
  });
}

template class PupilSpectrum<float>;
template class PupilSpectrum<double>;

}  // namespace glarelab
