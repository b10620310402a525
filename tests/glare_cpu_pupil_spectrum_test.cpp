// glare/cpu/pupil_spectrum.h in float32 and float64 against the float64 reference transform of
// glare/cpu/psf.h (compute_monochromatic_psf: FFTW's 2D plan on the same aperture), value by value
// down the PSF's tail: why the spectral PSF with a refraction takes the float64 form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "glare/cpu/psf.h"
#include "glare/cpu/pupil_spectrum.h"
#include "glare/eye/aperture_raster.h"

namespace glarelab {
namespace {

constexpr int kGridPx = 512;
constexpr double kWidthMm = 8.0, kPupilMm = 4.0, kWavelengthNm = 575.0;

struct TailAgreement {
  double worst_relative = 0.0;  // over the values at or above 1e-8 of the peak
  int tail_values = 0;          // of them, those below 1e-4 of the peak
};

// The normalised power of `spectrum` against the reference PSF, value by value.
template <typename Real>
TailAgreement tail_agreement(const PupilSpectrum<Real>& spectrum, const Psf& reference) {
  const Real* power = spectrum.power_column_major();
  double sum = 0.0, peak = 0.0;
  for (int k = 0; k < kGridPx * kGridPx; ++k) sum += power[k];
  for (int y = 0; y < kGridPx; ++y)
    for (int x = 0; x < kGridPx; ++x) peak = std::max(peak, reference.at(0, x, y));
  TailAgreement agreement;
  for (int y = 0; y < kGridPx; ++y)
    for (int x = 0; x < kGridPx; ++x) {
      const double expected = reference.at(0, x, y);
      if (expected < 1e-8 * peak) continue;
      if (expected < 1e-4 * peak) ++agreement.tail_values;
      const double value = power[static_cast<std::size_t>(x) * kGridPx + y] / sum;
      agreement.worst_relative = std::max(agreement.worst_relative, std::abs(value - expected) / expected);
    }
  return agreement;
}

TEST(PupilSpectrum, Float64KeepsTheTailThatFloat32Loses) {
  ApertureGeometry myope;
  myope.pupil_diameter_mm = kPupilMm;
  myope.refraction_error = DioptricPower::spherical(-2.0);
  ApertureRasterOptions raster;
  raster.grid_px = kGridPx;
  raster.aperture_width_mm = kWidthMm;
  raster.supersampling = 2;
  const ApertureGrid grid = rasterise_aperture(myope, raster);
  MonochromaticPsfOptions options;
  options.raster = raster;
  options.wavelength_nm = kWavelengthNm;
  const Psf reference = compute_monochromatic_psf(grid, kPupilMm, myope.total_power_error(), options).psf;

  PupilSpectrum<double> float64(kGridPx, 2);
  float64.transform(grid, PhaseForm::defocus, kPupilMm, myope.total_power_error(), kWavelengthNm);
  PupilSpectrum<float> float32(kGridPx, 2);
  float32.transform(grid, PhaseForm::defocus, kPupilMm, myope.total_power_error(), kWavelengthNm);
  const TailAgreement in_double = tail_agreement(float64, reference);
  const TailAgreement in_float = tail_agreement(float32, reference);
  std::printf("pupil spectrum tail (%d values in [1e-8, 1e-4] of the peak): float64 worst relative %.2e, float32 %.2e\n",
              in_double.tail_values, in_double.worst_relative, in_float.worst_relative);
  ASSERT_GT(in_double.tail_values, 100000);
  // Float64 in another order than the reference's 2D plan: roundings of 1.1e-16 of the largest
  // amplitude, 1e-4 of which is still 1e-2 of the peak's amplitude.
  EXPECT_LT(in_double.worst_relative, 1e-9);
  // Float32: 6e-8 of the largest amplitude is 6e-6 of an amplitude 1e-2 of it, 1e-4 in power, and
  // more further out.
  EXPECT_GT(in_float.worst_relative, 1e-4);
}

TEST(PupilSpectrum, RefusesAnOddGridAndAnotherGridsAperture) {
  EXPECT_THROW(PupilSpectrum<double>(511, 1), std::invalid_argument);
  EXPECT_THROW(PupilSpectrum<float>(0, 1), std::invalid_argument);
  ApertureGeometry eye;
  eye.pupil_diameter_mm = kPupilMm;
  ApertureRasterOptions raster;
  raster.grid_px = 256;
  raster.aperture_width_mm = kWidthMm;
  const ApertureGrid grid = rasterise_aperture(eye, raster);
  PupilSpectrum<double> spectrum(kGridPx, 1);
  EXPECT_THROW(spectrum.transform(grid, PhaseForm::defocus, kPupilMm, DioptricPower{}, kWavelengthNm), std::logic_error);
  PupilSpectrum<double> right(256, 1);
  EXPECT_THROW(right.transform(grid, PhaseForm::defocus, kPupilMm, DioptricPower{}, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab
