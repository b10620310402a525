// Monochromatic CPU PSF against closed forms: the Airy ring, Parseval, unit sums, wavelength
// scaling, the lenticular halo of radial fibre gratings, extreme pupils and grids, float vs double.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "glare/eye/fibre_gratings.h"
#include "glare/cpu/psf.h"
#include "glare_psf_test_support.h"

namespace glarelab {
namespace {

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

MonochromaticPsfOptions pupil_only_options(int grid_px, double width_mm, double wavelength_nm) {
  MonochromaticPsfOptions options;
  options.raster.grid_px = grid_px;
  options.raster.aperture_width_mm = width_mm;
  options.raster.supersampling = 2;
  options.wavelength_nm = wavelength_nm;
  options.phase = PhaseForm::none;
  return options;
}

TEST(GlarePsf, AiryFirstDarkRingAt122LambdaOverD) {
  // 4 mm pupil, 550 nm: first zero of the Airy pattern at 1.22 lambda / D (Born & Wolf 8.5.2).
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 4.0;
  const auto result = compute_monochromatic_psf(geometry, pupil_only_options(2048, 64.0, 550.0));
  const auto profile = test::radial_profile(result.psf);
  const double expected_deg = 1.22 * 550e-9 / 4e-3 * kDegreesPerRadian;
  const double expected_px = expected_deg / result.psf.degrees_per_pixel;  // 19.5 px
  // The first minimum of the profile after the central peak.
  std::size_t k = 1;
  while (k + 1 < profile.size() && !(profile[k] < profile[k - 1] && profile[k] <= profile[k + 1])) ++k;
  const double ring_deg = test::parabolic_vertex(profile, k) * result.psf.degrees_per_pixel;
  const double relative_error = std::abs(ring_deg - expected_deg) / expected_deg;
  RecordProperty("ring_relative_error", std::to_string(relative_error));
  std::printf("Airy ring: %.6f deg (expected %.6f deg, %.2f px), relative error %.4f\n", ring_deg, expected_deg,
              expected_px, relative_error);
  EXPECT_LT(relative_error, 0.02);
  EXPECT_NEAR(test::channel_sum(result.psf, 0), 1.0, 1e-9);
}

TEST(GlarePsf, ParsevalBeforeNormalisation) {
  // Discrete Parseval: sum |FFT(a)|^2 = N^2 sum |a|^2, with a lens particle and a fibre to make
  // the aperture non-trivial.
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 5.0;
  geometry.discs.push_back({0.7, -0.4, 0.3, 0.2});
  geometry.lines.push_back({-2.0, 1.0, 1.5, 0.2, 0.05, 0.5});
  geometry.defocus_dioptres = 0.5;
  auto options = pupil_only_options(512, 8.0, 600.0);
  options.phase = PhaseForm::defocus;
  const auto result = compute_monochromatic_psf(geometry, options);
  const double n2 = 512.0 * 512.0;
  EXPECT_NEAR(result.unnormalised_sum / (n2 * result.aperture_energy), 1.0, 1e-9);
  EXPECT_TRUE(result.sampling_warning.empty()) << result.sampling_warning;
  EXPECT_NEAR(test::channel_sum(result.psf, 0), 1.0, 1e-9);
}

TEST(GlarePsf, WavelengthScalingInAngle) {
  // Without the Fresnel term, PSF_l2(theta) = PSF_l1(l1 / l2 theta) as a density per solid angle
  // (Ritschel et al. 2009, section 5). Compare in degrees through each PSF's own degrees_per_pixel.
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 3.0;
  geometry.discs.push_back({0.5, 0.3, 0.2, 0.0});
  // Different aperture widths, so the two rasters and angular grids differ (10.0 vs 12.0 urad per
  // pixel) and the comparison goes through a real resampling.
  const auto psf_450 = compute_monochromatic_psf(geometry, pupil_only_options(1024, 45.0, 450.0)).psf;
  const auto psf_650 = compute_monochromatic_psf(geometry, pupil_only_options(1024, 54.0, 650.0)).psf;
  const int n = psf_650.size_px;
  const double density_450 = 1.0 / (psf_450.degrees_per_pixel * psf_450.degrees_per_pixel);
  const double density_650 = 1.0 / (psf_650.degrees_per_pixel * psf_650.degrees_per_pixel);
  // Central region: within 6 Airy radii at 650 nm.
  const double radius_deg = 6.0 * 1.22 * 650e-9 / 3e-3 * kDegreesPerRadian;
  double difference2 = 0.0, reference2 = 0.0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double ax = (x - n / 2) * psf_650.degrees_per_pixel, ay = (y - n / 2) * psf_650.degrees_per_pixel;
      if (std::hypot(ax, ay) > radius_deg) continue;
      // PSF_650 at angle a equals PSF_450 at angle a * 450 / 650.
      const double sx = ax * 450.0 / 650.0 / psf_450.degrees_per_pixel + n / 2;
      const double sy = ay * 450.0 / 650.0 / psf_450.degrees_per_pixel + n / 2;
      // Densities per square degree; the scaled copy is a density in the scaled angle, so it
      // carries the Jacobian (450/650)^2 to stay normalised.
      const double predicted = test::bilinear(psf_450, 0, sx, sy) * density_450 * (450.0 / 650.0) * (450.0 / 650.0);
      const double actual = psf_650.at(0, x, y) * density_650;
      difference2 += (predicted - actual) * (predicted - actual);
      reference2 += actual * actual;
    }
  const double relative_l2 = std::sqrt(difference2 / reference2);
  std::printf("wavelength scaling 450 -> 650 nm: relative L2 %.3g\n", relative_l2);
  EXPECT_LE(relative_l2, 1e-2);
}

TEST(GlarePsf, RadialFibreGratingsGiveTheLenticularHaloAt3Degrees) {
  // Spencer et al. 1995 section 3.1.1 (after Simpson): lenticular halo at about 3 deg for 568 nm,
  // so the fibre period is 568 nm / sin(3 deg) = 10.85 um.
  const double period_um = grating_period_um(568.0, 3.0);
  EXPECT_NEAR(period_um, 10.853, 1e-3);
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 5.0;
  FibreGratingOptions gratings;
  gratings.inner_radius_mm = 1.5;
  gratings.outer_radius_mm = 2.5;
  gratings.period_um = period_um;
  add_radial_fibre_gratings(geometry, gratings);
  auto options = pupil_only_options(2048, 5.6, 568.0);
  const auto with_gratings = compute_monochromatic_psf(geometry, options).psf;
  ApertureGeometry pupil_only;
  pupil_only.pupil_diameter_mm = 5.0;
  const auto without = compute_monochromatic_psf(pupil_only, options).psf;

  const auto profile = test::radial_profile(with_gratings);
  const auto background = test::radial_profile(without);
  const double dpp = with_gratings.degrees_per_pixel;
  // Peak of the azimuthal average between 1 and 5.5 degrees (away from the central Airy core).
  const auto first = static_cast<std::size_t>(1.0 / dpp), last = static_cast<std::size_t>(5.5 / dpp);
  std::size_t peak = first;
  for (std::size_t k = first; k <= last; ++k)
    if (profile[k] > profile[peak]) peak = k;
  const double peak_deg = test::parabolic_vertex(profile, peak) * dpp;
  std::printf("lenticular halo peak: %.4f deg (%zu px at %.6f deg/px), %.3g times the pupil-only profile\n", peak_deg,
              peak, dpp, profile[peak] / background[peak]);
  EXPECT_NEAR(peak_deg, 3.0, 0.15);
  // The halo is the gratings' doing: far above what the bare pupil sends there.
  EXPECT_GT(profile[peak], 100.0 * background[peak]);
}

TEST(GlarePsf, ExtremePupilsAndGridsStayFiniteAndNormalised) {
  // 256 and 2048: a 4096 grid costs about 5 s per PSF on the 2 shared cores of the test machine
  // (67 M sub-samples and a 256 MiB complex FFT); bench/glare_cpu_bench.cpp covers the large sizes.
  for (double pupil_mm : {1.5, 9.0}) {
    for (int grid_px : {256, 2048}) {
      ApertureGeometry geometry;
      geometry.pupil_diameter_mm = pupil_mm;
      auto options = pupil_only_options(grid_px, 2.0 * pupil_mm, 575.0);
      const auto result = compute_monochromatic_psf(geometry, options);
      EXPECT_TRUE(std::all_of(result.psf.values.begin(), result.psf.values.end(),
                              [](double v) { return std::isfinite(v) && v >= 0.0; }))
          << pupil_mm << " mm at " << grid_px;
      EXPECT_NEAR(test::channel_sum(result.psf, 0), 1.0, 1e-9) << pupil_mm << " mm at " << grid_px;
      // DC sits at the centre and is the brightest pixel of an in-focus pupil (Airy peak).
      const auto max_it = std::max_element(result.psf.values.begin(), result.psf.values.end());
      EXPECT_EQ(max_it - result.psf.values.begin(), static_cast<long>(grid_px / 2) * grid_px + grid_px / 2);
    }
  }
}

// Relative error of the first dark ring of a pupil-only PSF against 1.22 lambda / D.
double airy_ring_relative_error(const Psf& psf, double pupil_mm, double wavelength_nm) {
  const auto profile = test::radial_profile(psf);
  std::size_t k = 1;
  while (k + 1 < profile.size() && !(profile[k] < profile[k - 1] && profile[k] <= profile[k + 1])) ++k;
  const double expected_deg = 1.22 * wavelength_nm * 1e-6 / pupil_mm * kDegreesPerRadian;
  return std::abs(test::parabolic_vertex(profile, k) * psf.degrees_per_pixel - expected_deg) / expected_deg;
}

TEST(GlarePsf, SmallestAndLargestPupilsAtTheSmallestAndLargestGrids) {
  // 1.5 and 9 mm at N = 256 and 4096 (the largest grid; 1-2 s per PSF on the two shared
  // cores). N = 256 spans W = 16 D: the pupil covers 16 pixels, the ring lies at 1.22 W / D = 19.5
  // PSF pixels. N = 4096 spans one W = 96 mm for both: the 1.5 mm pupil covers 64 pixels (ring at
  // 78 px), the 9 mm one 384 (ring at 13 px).
  for (const int grid_px : {256, 4096})
    for (const double pupil_mm : {1.5, 9.0}) {
      ApertureGeometry geometry;
      geometry.pupil_diameter_mm = pupil_mm;
      const double width_mm = grid_px == 256 ? 16.0 * pupil_mm : 96.0;
      const auto result = compute_monochromatic_psf(geometry, pupil_only_options(grid_px, width_mm, 575.0));
      const double ring_error = airy_ring_relative_error(result.psf, pupil_mm, 575.0);
      std::printf("N = %d, pupil %.1f mm: Airy ring relative error %.2e, sum - 1 = %.1e\n", grid_px, pupil_mm, ring_error,
                  test::channel_sum(result.psf, 0) - 1.0);
      EXPECT_LT(ring_error, 0.02) << grid_px << " px, " << pupil_mm << " mm";
      EXPECT_NEAR(test::channel_sum(result.psf, 0), 1.0, 1e-9) << grid_px << " px, " << pupil_mm << " mm";
    }
}

TEST(GlarePsf, FloatPathMatchesDoublePath) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 6.0;
  geometry.discs.push_back({-1.0, 0.5, 0.4, 0.3});
  geometry.defocus_dioptres = 0.75;
  auto options = pupil_only_options(1024, 12.0, 575.0);
  options.phase = PhaseForm::defocus;
  const auto reference = compute_monochromatic_psf(geometry, options).psf;
  options.precision = FftPrecision::float32;
  const auto single = compute_monochromatic_psf(geometry, options).psf;
  double difference2 = 0.0, reference2 = 0.0;
  for (std::size_t k = 0; k < reference.values.size(); ++k) {
    difference2 += (single.values[k] - reference.values[k]) * (single.values[k] - reference.values[k]);
    reference2 += reference.values[k] * reference.values[k];
  }
  const double relative_l2 = std::sqrt(difference2 / reference2);
  std::printf("float vs double PSF (1024): relative L2 %.3g\n", relative_l2);
  EXPECT_LT(relative_l2, 1e-5);
}

TEST(GlarePsf, PaperFresnelTermIsReportedAsAliased) {
  // Eq. 3 with d = 24 mm over a 9 mm pupil needs dx < lambda d / (2 r) = 1.01 um at 380 nm.
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 9.0;
  auto options = pupil_only_options(256, 10.0, 380.0);
  options.phase = PhaseForm::paper;
  const auto result = compute_monochromatic_psf(geometry, options);
  EXPECT_NE(result.sampling_warning.find("aliased"), std::string::npos);
  options.strict_sampling = true;
  EXPECT_THROW(compute_monochromatic_psf(geometry, options), std::runtime_error);
  const auto report = check_phase_sampling(phase_coefficient_per_m2(PhaseForm::paper, 380.0, 0.0), 4.5, 10.0 / 256, 10.0);
  EXPECT_NEAR(report.max_pixel_mm * 1e3, 380e-9 * 0.024 / (2 * 4.5e-3) * 1e6, 1e-9);
  EXPECT_EQ(report.required_grid_px, 9869);  // ceil(10 mm / 1.0133 um)
}

}  // namespace
}  // namespace glarelab
