#pragma once
// The power spectrum of a rasterised pupil, |FFT(A exp(i phi))|^2 shifted so the DC term sits at
// (N/2, N/2) (Ritschel et al. 2009, Eq. 3, before its normalisation K), with the FFTW plan and every
// buffer made once for one grid size: the transform of the planned CPU path, in float32 for the
// monochromatic PSF of a stream of frames (glare/cpu/float_psf.h) and in float64 for the spectral PSF
// with the eye's LCA (glare/cpu/planned_chromatic_psf.h), whose dim tails a float32 transform leaves
// too coarse (docs/REFRACTION.md). Not thread-safe (buffers are reused from call to call).
#include <complex>
#include <string>
#include <type_traits>
#include <vector>

#include "glare/cpu/fftw_double_plan.h"
#include "glare/cpu/fftw_float_plan.h"
#include "glare/eye/aperture_raster.h"
#include "glare/refraction/dioptric_power.h"
#include "glare/wave/fresnel.h"

namespace glarelab {

template <typename Real>
class PupilSpectrum {
 public:
  // Throws std::invalid_argument for an odd grid or one below 2.
  PupilSpectrum(int grid_px, int threads);
  int grid_px() const { return grid_px_; }

  // The pupil function of `grid` (rasterised on grid_px) with the phase of `error` at wavelength_nm
  // (glare/wave/fresnel.h's quadratic phase of its one power for a spherical error or the forms none
  // and paper; glare/refraction/astigmatic_phase.h's for an astigmatic error with the defocus form),
  // transformed: the rows that can meet the pupil, then every column. Throws ClosedApertureError when
  // no light passes; an aliased phase leaves sampling_warning() non-empty.
  void transform(const ApertureGrid& grid, PhaseForm phase, double pupil_diameter_mm, const DioptricPower& error,
                 double wavelength_nm);

  // |FFT|^2 shifted, unnormalised, N x N column-major: pixel (x, y) at [x N + y].
  const Real* power_column_major() const { return power_.data(); }
  // The pupil function the last transform() handed the FFT, N x N row-major, row 0 at the top.
  const std::complex<Real>* field() const { return field_.data(); }
  const std::string& sampling_warning() const { return sampling_warning_; }

 private:
  using RowPlan = std::conditional_t<std::is_same_v<Real, float>, FftwFloatPlan, FftwDoublePlan>;
  // Clears what the last transform wrote outside rows [first_row, last_row] of field_ and columns_.
  void clear_stale_rows(int first_row, int last_row);
  // The phase of one transform, worked out once from the error and the form (transform()).
  struct PupilPhase {
    const DioptricPower& error;
    double wavelength_nm;
    bool astigmatic;     // the general form (glare/refraction/astigmatic_phase.h)
    double coefficient;  // else fresnel.h's pi c r^2, per m^2 (0: no phase)
  };
  // Writes rows [first_row, last_row] of the pupil function and their transforms, tile by tile,
  // transposed into columns_; returns the aperture's energy sum |A|^2.
  double transform_pupil_rows(const ApertureGrid& grid, const PupilPhase& phase, int first_row, int last_row);

  int grid_px_ = 0;
  int threads_ = 1;
  // The 2D FFT as two passes of contiguous 1D transforms (one plan). First the rows of the field that
  // can meet the pupil (the others are 0, and so are their transforms), kRowTile at a time into a
  // thread's tile, each tile written transposed into columns_ (columns_[u][row] = row's DFT at u; the
  // other rows' entries stay 0). Then every row of columns_ into spectrum_, which so holds the 2D DFT
  // transposed: spectrum_[u][v] = F(v, u). FFTW_ESTIMATE's own 2D plan walks the columns at a stride
  // of N complex values, and a power-of-two stride maps a column onto few cache sets
  // (docs/PERFORMANCE.md, "Measurements behind the code's choices").
  static constexpr int kRowTile = 16;
  FftwFloatBuffer<std::complex<Real>> field_, columns_, spectrum_, row_tiles_;
  FftwFloatBuffer<Real> power_;
  RowPlan row_fft_;
  std::string sampling_warning_;
  std::vector<double> row_energy_;                  // sum |A|^2 per aperture row
  std::vector<std::complex<double>> phase_factor_;  // exp(i pi c x^2) per column of the pupil
  int written_first_row_ = 0, written_last_row_ = -1;  // field rows the last transform wrote
};

extern template class PupilSpectrum<float>;
extern template class PupilSpectrum<double>;

}  // namespace glarelab
