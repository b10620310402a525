// The planned CPU spectral PSF with the eye's longitudinal chromatic aberration
// (glare/cpu/planned_chromatic_psf.h, and CpuFloatGlare with longitudinal_chromatic_aberration) against
// the CPU float64 reference compute_chromatic_psf (glare/wave/chromatic_psf.h), per channel, relative to
// the peak and in L2, for a myope, an oblique astigmat with scatterers and an emmetrope, and value by
// value down the dim tail (its float64 transforms' reason); the blue and
// red widths against the reference; the per-wavelength transform at the settings' wavelength bit for
// bit as the two-argument one; the refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "glare/wave/chromatic_psf.h"
#include "glare/cpu/planned_chromatic_psf.h"
#include "glare/cpu/float_glare.h"
#include "glare/cpu/float_psf.h"
#include "glare/eye/eye_model.h"
#include "glare/cpu/psf.h"
#include "glare/glare_benchmark.h"
#include "glare/wave/psf_scale.h"
#include "psf_agreement.h"

namespace glarelab {
namespace {

using test::Agreement;
using test::compare_channel;
using test::rms_radius_px;

// As tests/glare_gl_chromatic_test.cpp: 512 px over 8 mm, a 4 mm pupil; no wavelength aliases.
constexpr int kGridPx = 512;
constexpr double kWidthMm = 8.0, kPupilMm = 4.0, kReferenceNm = 575.0;
constexpr int kWavelengths = 16;

// An uncorrected eye looking far: its residual error is minus its correcting prescription.
ApertureGeometry eye_with_prescription(const SpheroCylinder& prescription) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = kPupilMm;
  geometry.refraction_error = DioptricPower::from_prescription(prescription) * -1.0;
  return geometry;
}

ChromaticPsfResult reference(const ApertureGeometry& geometry, int grid_px = kGridPx) {
  ChromaticPsfOptions options;
  options.raster.grid_px = grid_px;
  options.raster.aperture_width_mm = kWidthMm;
  options.raster.supersampling = 2;
  options.reference_wavelength_nm = kReferenceNm;
  options.wavelength_samples = kWavelengths;
  return compute_chromatic_psf(geometry, options);
}

CpuFloatPsfSettings psf_settings() {
  CpuFloatPsfSettings settings;
  settings.raster.grid_px = kGridPx;
  settings.raster.aperture_width_mm = kWidthMm;
  settings.raster.supersampling = 2;
  settings.wavelength_nm = kReferenceNm;
  return settings;
}

CpuPlannedChromaticSettings chromatic_settings() {
  CpuPlannedChromaticSettings settings;
  settings.grid_px = kGridPx;
  settings.aperture_width_mm = kWidthMm;
  settings.reference_wavelength_nm = kReferenceNm;
  settings.wavelength_samples = kWavelengths;
  return settings;
}

TEST(GlareCpuPlannedChromatic, MatchesTheFloat64ReferenceForAMyopeAnObliqueAstigmatAndAnEmmetrope) {
  struct Eye {
    const char* name;
    SpheroCylinder prescription;
    bool scatterers;
  };
  const Eye eyes[] = {{"myope -2", {-2.0, 0.0, 0.0}, false},
                      {"astigmat -1 / -1.5 x 30", {-1.0, -1.5, 30.0}, true},
                      {"emmetrope", {0.0, 0.0, 0.0}, false}};
  CpuFloatPsf psf(psf_settings());
  CpuPlannedChromaticPsf chromatic(chromatic_settings());
  for (const Eye& eye : eyes) {
    ApertureGeometry geometry = eye_with_prescription(eye.prescription);
    if (eye.scatterers) {
      geometry.discs = {{1.0, 0.5, 0.3, 0.2}, {-1.5, -1.0, 0.6, 0.0}};
      geometry.lines = {{-2.0, 1.5, 2.0, 0.5, 0.1, 0.3}};
    }
    const ChromaticPsfResult expected = reference(geometry);
    ASSERT_EQ(expected.aliased_wavelengths, 0) << eye.name << ": " << expected.sampling_warning;
    psf.rasterise(geometry);
    const SpectralPsfResult result = chromatic.compute(psf, geometry.pupil_diameter_mm, geometry.total_power_error());
    EXPECT_EQ(chromatic.aliased_wavelengths(), 0);
    EXPECT_TRUE(chromatic.sampling_warning().empty());
    EXPECT_DOUBLE_EQ(result.psf.degrees_per_pixel, expected.spectral.psf.degrees_per_pixel);
    for (int c = 0; c < 3; ++c) {
      const Agreement agreement = compare_channel(result.psf, expected.spectral.psf, c);
      std::printf("planned chromatic %-26s channel %c: max error / peak %.2e, relative L2 %.2e\n", eye.name, "RGB"[c],
                  agreement.max_over_peak, agreement.relative_l2);
      // Float64 transforms in another order than the reference's (two passes of row transforms
      // against FFTW's 2D plan, the phase as a product of a row and a column factor, the resampling
      // separable): a few thousand roundings of 1.1e-16 at most. A float32 transform gave 7.8e-9 here.
      EXPECT_LT(agreement.max_over_peak, 1e-13) << eye.name << " channel " << c;
      EXPECT_LT(agreement.relative_l2, 1e-12) << eye.name << " channel " << c;
      EXPECT_GT(agreement.relative_l2, 0.0) << eye.name << " channel " << c;  // its own transforms, not the reference's
      EXPECT_NEAR(result.clamped_negative_fraction[c], expected.spectral.clamped_negative_fraction[c], 1e-6);
    }
  }
}

// A dim pixel beside a lamp takes its glare from the PSF's tail, a sum of many values a million
// times below the peak and less. A float32 transform's error there is a fraction of the largest
// amplitude, not of the value: the presbyope example's dim wall moved by 6e-6 of its value with one
// (docs/REFRACTION.md). Each value here keeps the reference's to 1e-9 of itself down to 1e-8 of the
// peak (tests/glare_cpu_pupil_spectrum_test.cpp shows a float32 transform off by more than 1e-4 there).
TEST(GlareCpuPlannedChromatic, KeepsTheReferencesDimTailValueByValue) {
  const ApertureGeometry myope = eye_with_prescription({-2.0, 0.0, 0.0});
  const ChromaticPsfResult expected = reference(myope);
  CpuFloatPsf psf(psf_settings());
  psf.rasterise(myope);
  CpuPlannedChromaticPsf chromatic(chromatic_settings());
  const SpectralPsfResult result = chromatic.compute(psf, kPupilMm, myope.total_power_error());
  for (int c = 0; c < 3; ++c) {
    double peak = 0.0;
    for (int y = 0; y < kGridPx; ++y)
      for (int x = 0; x < kGridPx; ++x) peak = std::max(peak, expected.spectral.psf.at(c, x, y));
    double worst = 0.0;
    int tail_values = 0;
    for (int y = 0; y < kGridPx; ++y)
      for (int x = 0; x < kGridPx; ++x) {
        const double value = expected.spectral.psf.at(c, x, y);
        if (value < 1e-8 * peak) continue;
        if (value < 1e-4 * peak) ++tail_values;
        worst = std::max(worst, std::abs(result.psf.at(c, x, y) - value) / value);
      }
    std::printf("planned chromatic tail, channel %c: %d values in [1e-8, 1e-4] of the peak, worst relative %.2e\n",
                "RGB"[c], tail_values, worst);
    EXPECT_GT(tail_values, 10000) << "channel " << c;  // the tail is there to be checked
    EXPECT_LT(worst, 1e-9) << "channel " << c;
  }
}

TEST(GlareCpuPlannedChromatic, EmmetropeBlueIsWiderThanRedAsTheReferenceSays) {
  const ApertureGeometry emmetrope = eye_with_prescription({0.0, 0.0, 0.0});
  const Psf expected = reference(emmetrope).spectral.psf;
  CpuFloatPsf psf(psf_settings());
  CpuPlannedChromaticPsf chromatic(chromatic_settings());
  psf.rasterise(emmetrope);
  const Psf result = chromatic.compute(psf, kPupilMm, emmetrope.total_power_error()).psf;
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(rms_radius_px(result, c) / rms_radius_px(expected, c), 1.0, 1e-5) << "channel " << c;
  EXPECT_GT(rms_radius_px(result, 2) / rms_radius_px(result, 0), 1.5);
}

TEST(GlareCpuPlannedChromatic, ReportsTheAliasedWavelengthsAsTheReferenceDoes) {
  // At N = 256 over 8 mm the blue end of these two eyes' spectra aliases.
  CpuFloatPsfSettings settings = psf_settings();
  settings.raster.grid_px = 256;
  CpuFloatPsf psf(settings);
  CpuPlannedChromaticSettings chromatic_256 = chromatic_settings();
  chromatic_256.grid_px = 256;
  CpuPlannedChromaticPsf chromatic(chromatic_256);
  for (const SpheroCylinder& prescription : {SpheroCylinder{-2.0, 0.0, 0.0}, SpheroCylinder{-1.0, -1.5, 30.0}}) {
    const ApertureGeometry geometry = eye_with_prescription(prescription);
    const ChromaticPsfResult expected = reference(geometry, 256);
    psf.rasterise(geometry);
    (void)chromatic.compute(psf, kPupilMm, geometry.total_power_error());
    EXPECT_GT(expected.aliased_wavelengths, 0);
    EXPECT_EQ(chromatic.aliased_wavelengths(), expected.aliased_wavelengths);
    EXPECT_EQ(chromatic.sampling_warning(), expected.sampling_warning);
  }
}

TEST(GlareCpuPlannedChromatic, TransformAtTheSettingsWavelengthIsTheTwoArgumentOne) {
  ApertureGeometry geometry = eye_with_prescription({-0.5, -2.0, 45.0});
  geometry.discs = {{1.0, 0.5, 0.3, 0.2}};
  CpuFloatPsfSettings settings = psf_settings();
  settings.raster.grid_px = 128;
  CpuFloatPsf psf(settings);
  psf.rasterise(geometry);
  psf.transform(kPupilMm, geometry.total_power_error());
  const std::vector<float> two(psf.power_column_major(), psf.power_column_major() + 128 * 128);
  psf.transform(kPupilMm, geometry.total_power_error(), 450.0);  // something else in between
  psf.transform(kPupilMm, geometry.total_power_error(), kReferenceNm);
  const std::vector<float> three(psf.power_column_major(), psf.power_column_major() + 128 * 128);
  EXPECT_EQ(two, three);
  EXPECT_THROW(psf.transform(kPupilMm, geometry.total_power_error(), 0.0), std::invalid_argument);
}

TEST(GlareCpuPlannedChromatic, GlareDisplayPsfIsTheResampledReferenceWithLca) {
  // CpuFloatGlare with longitudinal_chromatic_aberration: the N x N chromatic PSF, box-resampled onto
  // the display as the float64 path resamples compute_chromatic_psf's result.
  const ApertureGeometry geometry = eye_with_prescription({-1.0, -1.5, 30.0});
  CpuFloatGlareSettings settings;
  settings.grid_px = kGridPx;
  settings.aperture_width_mm = kWidthMm;
  settings.wavelength_samples = kWavelengths;
  settings.reference_wavelength_nm = kReferenceNm;
  settings.display_degrees_per_pixel = 4.0 * psf_degrees_per_pixel(kReferenceNm, kWidthMm);
  settings.longitudinal_chromatic_aberration = true;
  CpuFloatGlare glare(settings);
  const Psf display = glare.display_psf(geometry);
  const Psf expected = resample_psf_to_display(reference(geometry).spectral.psf, settings.display_degrees_per_pixel);
  ASSERT_EQ(display.size_px, expected.size_px);
  for (int c = 0; c < 3; ++c) {
    const Agreement agreement = compare_channel(display, expected, c);
    std::printf("planned chromatic display PSF channel %c: max error / peak %.2e, relative L2 %.2e\n", "RGB"[c],
                agreement.max_over_peak, agreement.relative_l2);
    // The float64 transforms (above), box-resampled as the reference is.
    EXPECT_LT(agreement.max_over_peak, 1e-13) << "channel " << c;
    EXPECT_LT(agreement.relative_l2, 1e-12) << "channel " << c;
  }
  EXPECT_TRUE(glare.sampling_warning().empty());
  // Without the flag the same eye gives the scaled-reference PSF, which differs by the LCA blur.
  settings.longitudinal_chromatic_aberration = false;
  CpuFloatGlare scaled(settings);
  EXPECT_GT(compare_channel(scaled.display_psf(geometry), expected, 2).relative_l2, 1e-2);
}

TEST(GlareCpuPlannedChromatic, RefusesBadSettingsAndAnotherGrid) {
  CpuPlannedChromaticSettings settings = chromatic_settings();
  settings.wavelength_samples = 0;
  EXPECT_THROW(CpuPlannedChromaticPsf{settings}, std::invalid_argument);
  settings = chromatic_settings();
  settings.reference_wavelength_nm = 200.0;  // at or below the LCA fit's pole (214.1 nm)
  EXPECT_THROW(CpuPlannedChromaticPsf{settings}, std::invalid_argument);
  settings = chromatic_settings();
  settings.grid_px = 7;
  EXPECT_THROW(CpuPlannedChromaticPsf{settings}, std::invalid_argument);
  CpuPlannedChromaticPsf chromatic(chromatic_settings());
  CpuFloatPsfSettings other = psf_settings();
  other.raster.grid_px = 256;
  CpuFloatPsf psf(other);
  psf.rasterise(eye_with_prescription({-2.0, 0.0, 0.0}));
  EXPECT_THROW(chromatic.compute(psf, kPupilMm, DioptricPower{}), std::invalid_argument);
}

TEST(GlareBenchmarkRefraction, EveryCpuPathTimesThePhaseOfTheWholePowerError) {
  // `glarelab bench` with a refraction: each CPU row's PSF at N is compared with the float64 PSF of
  // the 2N grid computed from the same geometry (compute_monochromatic_psf(geometry), which takes the
  // whole power error). A row that dropped the refraction would differ from it by the refraction's
  // blur, which the test measures here from the eye model at the same instant, 2N, with and without.
  GlareBenchmarkOptions options;
  options.grid_sizes = {128};
  options.frames = 1;
  options.wavelength_samples = 8;
  options.refraction_error = DioptricPower::from_prescription({-0.25, -0.5, 30.0}) * -1.0;
  const GlareBenchmarkResult result = run_glare_benchmark(options);
  ASSERT_EQ(result.rows.size(), 3u);  // float64, float32, float32 planned (no GL context)
  double worst = 0.0;
  for (const GlareBenchmarkRow& row : result.rows) {
    std::printf("bench with -0.25 / -0.5 x 30: %-20s discretisation %.2e, PSF error %.2e, frame error %.2e\n",
                std::string(spelling(row.backend)).c_str(), row.discretisation_error, row.psf_error, row.frame_error);
    worst = std::max(worst, row.discretisation_error);
    EXPECT_LT(row.psf_error, 1e-5) << spelling(row.backend);
    // The planned path's display-scale clamp (glare/cpu/float_spectral_psf.h) is a screen, not a bound: on
    // this defocused, astigmatic PSF its frame error is 1.6e-5 (below 1e-6 on the eye model alone).
    EXPECT_LT(row.frame_error, 1e-4) << spelling(row.backend);
  }
  ASSERT_EQ(result.frames.size(), 1u);
  EXPECT_EQ(result.frames[0].discretisation_error, result.rows[2].discretisation_error);
  // What leaving the refraction out would cost: the 2N PSFs of the bench's eye (the instant it
  // picks: the first from time_s on, steps of 0.1 s, with no blink) with and without it.
  const EyeModel eye(EyeParameters{}, options.seed);
  double time_s = options.time_s;
  while (eye.state_at(time_s).blink_closure > 0.0) time_s += 0.1;
  ApertureGeometry geometry = eye.geometry_at(time_s);
  MonochromaticPsfOptions fine;
  fine.raster.grid_px = 256;
  fine.raster.aperture_width_mm = 10.0;
  const Psf plain = compute_monochromatic_psf(geometry, fine).psf;
  geometry.refraction_error = geometry.refraction_error + options.refraction_error;
  const Psf refracted = compute_monochromatic_psf(geometry, fine).psf;
  double difference = 0.0, norm = 0.0;
  for (std::size_t k = 0; k < plain.values.size(); ++k) {
    difference += (plain.values[k] - refracted.values[k]) * (plain.values[k] - refracted.values[k]);
    norm += refracted.values[k] * refracted.values[k];
  }
  const double dropped = std::sqrt(difference / norm);
  std::printf("the refraction's own effect on the 2N PSF: relative L2 %.2e\n", dropped);
  EXPECT_LT(worst, 0.1 * dropped);
}

}  // namespace
}  // namespace glarelab
