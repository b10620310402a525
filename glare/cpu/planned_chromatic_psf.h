#pragma once
// The spectral PSF with the eye's longitudinal chromatic aberration (LCA) of glare/wave/chromatic_psf.h
// (compute_chromatic_psf, the reference) on the planned CPU path: one float64 transform per
// wavelength (glare/cpu/pupil_spectrum.h: the FFTW plan and buffers made once per grid) of the
// aperture a CpuFloatPsf rasterised once (glare/cpu/float_psf.h), each with its own error
//
//   E(lambda) = E_ref + [LCA(lambda) - LCA(lambda_ref)] I
//
// (glare/refraction/chromatic_eye.h, Thibos et al. 1992), each |F|^2 normalised to sum 1, resampled onto the
// reference grid (bilinear about (N/2, N/2), reference pixel x read at source pixel
// (x - N/2) lambda_ref / lambda + N/2, zero outside, times the Jacobian (lambda_ref / lambda)^2) and
// added with the CIE 1931 CMF weights into XYZ: glare/wave/spectral_accumulation.h's operator, done here
// separably (each source row interpolated along x once per output row pair) on `threads` threads
// over output rows, and only over the output pixels a wavelength's PSF reaches; the XYZ planes go
// to linear Rec.709 by glare/wave/spectral_accumulation.h's own rec709_psf_from_xyz. The scaled-reference
// spectral PSF (glare/cpu/float_spectral_psf.h) is exact only for a phase that does not depend on
// wavelength; this one is the one to use for an eye with a refraction error or when LCA matters.
//
// Why float64 transforms. A float32 FFT's error is a fraction of the spectrum's largest amplitude,
// so in the PSF's far tail, 1e-6 of the peak and less, it is a large fraction of the value; a dim
// pixel's glare beside a lamp is the sum of many such tail values, and a float32 transform moved such
// a pixel by 6e-6 of its value (docs/REFRACTION.md). In float64 the tail keeps the reference's
// values; the transforms are a small part of this PSF's cost (the resampling, in double either way,
// is most of it: docs/PERFORMANCE.md).
// Not thread-safe (buffers are reused from call to call).
#include <string>
#include <vector>

#include "glare/wave/cie_cmf.h"
#include "glare/cpu/float_psf.h"
#include "glare/cpu/pupil_spectrum.h"
#include "glare/refraction/dioptric_power.h"
#include "glare/wave/spectral_accumulation.h"

namespace glarelab {

struct CpuPlannedChromaticSettings {
  int grid_px = 512;                       // N of the CpuFloatPsf it is used with
  double aperture_width_mm = 10.0;         // of that CpuFloatPsf's pupil-plane grid
  double reference_wavelength_nm = 575.0;  // lambda_ref: E_ref's wavelength and the output grid's
  int wavelength_samples = 32;             // Ritschel's lambda_i = 380 + i (770 - 380) / n nm
  int threads = kGlareCpuThreads;          // for the transforms and the resampling
};

class CpuPlannedChromaticPsf {
 public:
  // Throws std::invalid_argument (naming "glare/cpu/planned_chromatic_psf") for n < 1 wavelengths, an
  // odd or too small grid, and a reference wavelength that is not positive or that the LCA fit
  // cannot take (<= 214.1 nm).
  explicit CpuPlannedChromaticPsf(const CpuPlannedChromaticSettings& settings);

  // R, G, B on the reference grid (pixels of lambda_ref / W), each channel summing to 1. `psf` must
  // have rasterised the aperture (CpuFloatPsf::rasterise) on this grid (its phase form is used, its
  // float32 transform is not); reference_error is the eye's
  // whole power error at lambda_ref (ApertureGeometry::total_power_error()), dioptres. Throws
  // std::invalid_argument for a CpuFloatPsf of another grid, ClosedApertureError when no light passes.
  SpectralPsfResult compute(const CpuFloatPsf& psf, double pupil_diameter_mm, const DioptricPower& reference_error);

  // The last compute()'s sampling check, as compute_chromatic_psf reports it: the warning of the most
  // aliased wavelength with " (at X nm)", or empty; and how many wavelengths aliased.
  const std::string& sampling_warning() const { return sampling_warning_; }
  int aliased_wavelengths() const { return aliased_wavelengths_; }
  double degrees_per_pixel() const;

 private:
  struct Wavelength {
    double wavelength_nm = 0.0;
    double excess_dioptres = 0.0;  // LCA(lambda) - LCA(lambda_ref), added to E_ref
    Xyz cmf;
    // Per output pixel x (rows and columns alike): the two bilinear neighbours of the scaled
    // position, clamped onto the grid, with weight 0 for a neighbour outside it (it reads 0).
    std::vector<int> index0, index1;
    std::vector<double> weight0, weight1;
    int first_px = 0, last_px = -1;  // output pixels with a neighbour inside the grid
  };
  // Adds one wavelength's power spectrum (column-major, CpuFloatPsf's layout) times `scale` (CMF
  // weight / sum, Jacobian) into xyz_, which so holds column-major sums until compute() transposes it.
  void accumulate(const Wavelength& wavelength, const double* power, double scale);
  CpuPlannedChromaticSettings settings_;
  PupilSpectrum<double> spectrum_;
  std::vector<Wavelength> wavelengths_;
  XyzPlanes xyz_;
  std::string sampling_warning_;
  int aliased_wavelengths_ = 0;
};

}  // namespace glarelab
