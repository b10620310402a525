// The GPU PSF: the Airy pattern of a round pupil (first dark ring at 1.22 lambda / D), unit sums,
// and the monochromatic (with defocus) and spectral PSFs against a CPU double computation written
// here from the formulas (FFTW, bilinear resampling, CMF weights).
#include <fftw3.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <sstream>
#include <vector>

#include "glare/wave/cie_cmf.h"
#include "runner/display/compute_context.h"
#include "glare/gl/psf.h"

namespace glarelab {
namespace {

class GlPsfTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = gl::create_compute_context(); }
  static void TearDownTestSuite() { context_.reset(); }
  static std::unique_ptr<DisplayBackend> context_;
};
std::unique_ptr<DisplayBackend> GlPsfTest::context_;

std::string figure(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

double channel_sum(const Psf& psf, int channel) {
  double sum = 0.0;
  for (int y = 0; y < psf.size_px; ++y)
    for (int x = 0; x < psf.size_px; ++x) sum += psf.at(channel, x, y);
  return sum;
}

double bilinear(const std::vector<double>& grid, int n, double x, double y) {
  const auto at = [&](int i, int j) {
    return i < 0 || j < 0 || i >= n || j >= n ? 0.0 : grid[static_cast<std::size_t>(j) * n + i];
  };
  const int i = static_cast<int>(std::floor(x)), j = static_cast<int>(std::floor(y));
  const double fx = x - i, fy = y - j;
  return (1 - fy) * ((1 - fx) * at(i, j) + fx * at(i + 1, j)) + fy * ((1 - fx) * at(i, j + 1) + fx * at(i + 1, j + 1));
}

// |FFT(aperture * exp(i pi D r^2 / lambda))|^2, shifted and normalised, all in double.
std::vector<double> reference_psf(const std::vector<float>& aperture, int n, double dx_mm, double defocus_dioptres,
                                  double wavelength_nm) {
  std::vector<std::complex<double>> field(aperture.size());
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // Pixel centres of glare/eye/aperture_raster.h: the optical axis at the centre of pixel (n/2, n/2).
      const double x = (i - n / 2) * dx_mm, y = (n / 2 - j) * dx_mm;
      const double phase = std::numbers::pi * defocus_dioptres * (x * x + y * y) * 1e-6 / (wavelength_nm * 1e-9);
      field[static_cast<std::size_t>(j) * n + i] = double(aperture[static_cast<std::size_t>(j) * n + i]) * std::polar(1.0, phase);
    }
  fftw_plan plan = fftw_plan_dft_2d(n, n, reinterpret_cast<fftw_complex*>(field.data()),
                                    reinterpret_cast<fftw_complex*>(field.data()), FFTW_FORWARD, FFTW_ESTIMATE);
  fftw_execute(plan);
  fftw_destroy_plan(plan);
  std::vector<double> psf(field.size());
  double sum = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double value = std::norm(field[static_cast<std::size_t>((j + n / 2) % n) * n + (i + n / 2) % n]);
      psf[static_cast<std::size_t>(j) * n + i] = value;
      sum += value;
    }
  for (double& value : psf) value /= sum;
  return psf;
}

double relative_l2(const std::vector<double>& actual, const std::vector<double>& expected, std::size_t offset = 0) {
  double error = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    error += (actual[offset + i] - expected[i]) * (actual[offset + i] - expected[i]);
    norm += expected[i] * expected[i];
  }
  return std::sqrt(error / norm);
}

TEST_F(GlPsfTest, AiryFirstDarkRingAt122LambdaOverD) {
  const int n = 512;
  const double pupil_mm = 3.0, wavelength_nm = 550.0;
  gl::GlPsf gl_psf(n, 16.0 * pupil_mm, 4);
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = pupil_mm;
  const Psf psf = gl_psf.monochromatic(geometry, wavelength_nm);
  ASSERT_EQ(psf.channels, 1);
  EXPECT_NEAR(channel_sum(psf, 0), 1.0, 1e-5);
  // degrees_per_pixel = lambda / (N dx) in degrees.
  EXPECT_NEAR(psf.degrees_per_pixel, 550e-6 / 48.0 * 180.0 / std::numbers::pi, 1e-15);

  // Azimuthal mean over 360 directions, radius in steps of 0.01 px; the first minimum.
  const std::vector<double> grid(psf.values.begin(), psf.values.end());
  double best_radius = 0.0, best_value = 1e300;
  for (double radius = 10.0; radius <= 30.0; radius += 0.01) {
    double mean = 0.0;
    for (int k = 0; k < 360; ++k) {
      const double angle = 2.0 * std::numbers::pi * k / 360.0;
      mean += bilinear(grid, n, n / 2.0 + radius * std::cos(angle), n / 2.0 + radius * std::sin(angle));
    }
    if (mean < best_value) best_value = mean, best_radius = radius;
  }
  // First zero of J1(x)/x: x = 3.8317, i.e. theta = 3.8317 / pi lambda / D = 1.2197 lambda / D.
  const double expected_deg = 1.2197 * wavelength_nm * 1e-6 / pupil_mm * 180.0 / std::numbers::pi;
  const double measured_deg = best_radius * psf.degrees_per_pixel;
  RecordProperty("first_dark_ring_ratio", figure(measured_deg / expected_deg));
  EXPECT_NEAR(measured_deg / expected_deg, 1.0, 0.02) << "ring at " << best_radius << " px";
}

TEST_F(GlPsfTest, DefocusedBusyApertureMatchesDoubleReference) {
  const int n = 256;
  const double width_mm = 12.0, wavelength_nm = 600.0;
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 6.0;
  geometry.defocus_dioptres = 0.75;
  geometry.discs = {{1.0, 0.5, 0.3, 0.2}, {-1.5, -1.0, 0.6, 0.0}};
  geometry.lines = {{-3.0, 2.0, 3.0, 1.0, 0.1, 0.3}};
  gl::GlPsf gl_psf(n, width_mm, 2);
  const Psf psf = gl_psf.monochromatic(geometry, wavelength_nm);
  gl::GlAperture aperture(n, width_mm, 2);  // the same aperture, read back for the reference
  aperture.draw(geometry);
  const auto expected = reference_psf(aperture.read(), n, width_mm / n, geometry.defocus_dioptres, wavelength_nm);
  const double error = relative_l2(psf.values, expected);
  RecordProperty("defocus_psf_relative_l2", figure(error));
  EXPECT_LE(error, 1e-4);
  EXPECT_NEAR(channel_sum(psf, 0), 1.0, 1e-5);
}

TEST_F(GlPsfTest, SpectralMatchesDoubleReferenceAndSumsToOne) {
  const int n = 256, wavelengths = 32;
  const double width_mm = 16.0, reference_nm = 575.0;
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 4.0;
  geometry.lines = {{-2.0, 0.0, 2.0, 0.0, 0.05, 0.0}, {0.0, -2.0, 0.0, 2.0, 0.05, 0.0}};
  gl::GlPsf gl_psf(n, width_mm, 2);
  const Psf psf = gl_psf.spectral(geometry, wavelengths, reference_nm);
  ASSERT_EQ(psf.channels, 3);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(channel_sum(psf, c), 1.0, 1e-5) << "channel " << c;

  gl::GlAperture aperture(n, width_mm, 2);
  aperture.draw(geometry);
  const auto reference = reference_psf(aperture.read(), n, width_mm / n, 0.0, reference_nm);
  const std::size_t count = static_cast<std::size_t>(n) * n;
  std::vector<double> expected(3 * count, 0.0);
  for (const SpectralSample& sample : spectral_samples(wavelengths)) {
    const double k = reference_nm / sample.wavelength_nm;
    const double weight[3] = {sample.weight.r, sample.weight.g, sample.weight.b};
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double value = k * k * bilinear(reference, n, n / 2.0 + (x - n / 2.0) * k, n / 2.0 + (y - n / 2.0) * k);
        for (int c = 0; c < 3; ++c) expected[c * count + static_cast<std::size_t>(y) * n + x] += weight[c] * value;
      }
  }
  for (int c = 0; c < 3; ++c) {
    std::vector<double> channel(expected.begin() + static_cast<std::ptrdiff_t>(c * count),
                                expected.begin() + static_cast<std::ptrdiff_t>((c + 1) * count));
    double sum = 0.0;
    for (double& value : channel) sum += (value = std::max(value, 0.0));
    for (double& value : channel) value /= sum;
    const double error = relative_l2(psf.values, channel, c * count);
    RecordProperty("spectral_relative_l2_channel_" + std::to_string(c), figure(error));
    EXPECT_LE(error, 1e-4) << "channel " << c;
  }
  // Red light diffracts further than blue: the red channel's second moment is larger.
  const auto spread = [&](int c) {
    double moment = 0.0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) moment += psf.at(c, x, y) * ((x - n / 2.0) * (x - n / 2.0) + (y - n / 2.0) * (y - n / 2.0));
    return moment;
  };
  EXPECT_GT(spread(0), spread(2));
}

TEST_F(GlPsfTest, SameApertureGivesBitIdenticalPsf) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 5.0;
  for (int i = 0; i < 100; ++i) geometry.discs.push_back({0.04 * i - 2.0, 0.03 * i - 1.5, 0.1, 0.5});
  geometry.lines = {{-2.0, 1.0, 2.0, -1.0, 0.05, 0.2}};
  gl::GlPsf psf(128, 10.0, 2);
  const Psf first = psf.spectral(geometry, 16);
  psf.monochromatic(ApertureGeometry{}, 500.0);  // something else in between
  const Psf second = psf.spectral(geometry, 16);
  EXPECT_EQ(first.values, second.values);
}

TEST_F(GlPsfTest, RefusesGridsTheFftCannotTake) {
  EXPECT_THROW(gl::GlPsf(300, 8.0, 2), std::invalid_argument);
  gl::GlPsf psf(64, 8.0, 2);
  EXPECT_THROW(psf.monochromatic(ApertureGeometry{}, 0.0), std::invalid_argument);
  EXPECT_THROW(psf.spectral(ApertureGeometry{}, 0), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab
