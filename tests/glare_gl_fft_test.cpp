// The GL compute FFT against FFTW in double precision: random complex input, forward and inverse,
// Parseval's theorem, and the refusal of unsupported sizes.
#include <fftw3.h>
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "runner/display/compute_context.h"
#include "glare/gl/fft.h"
#include "core/random.h"

namespace glarelab {
namespace {

using Complex = std::complex<double>;

class GlFftTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = gl::create_compute_context(); }
  static void TearDownTestSuite() { context_.reset(); }
  static std::unique_ptr<DisplayBackend> context_;
};
std::unique_ptr<DisplayBackend> GlFftTest::context_;

std::vector<std::complex<float>> random_grid(std::size_t count, std::uint64_t seed) {
  const CounterRandom random(seed, RandomStream::glare_gl_test_input);
  std::vector<std::complex<float>> values(count);
  for (std::size_t i = 0; i < count; ++i)
    values[i] = {static_cast<float>(2.0 * random.uniform(i, 0) - 1.0), static_cast<float>(2.0 * random.uniform(i, 1) - 1.0)};
  return values;
}

// FFTW_FORWARD / FFTW_BACKWARD in double; both unnormalised.
std::vector<Complex> fftw_2d(const std::vector<std::complex<float>>& input, int width, int height, int sign) {
  std::vector<Complex> data(input.begin(), input.end());
  fftw_plan plan = fftw_plan_dft_2d(height, width, reinterpret_cast<fftw_complex*>(data.data()),
                                    reinterpret_cast<fftw_complex*>(data.data()), sign, FFTW_ESTIMATE);
  fftw_execute(plan);
  fftw_destroy_plan(plan);
  return data;
}

double relative_l2(const std::vector<std::complex<float>>& actual, const std::vector<Complex>& expected) {
  double error = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    error += std::norm(Complex(actual[i]) - expected[i]);
    norm += std::norm(expected[i]);
  }
  return std::sqrt(error / norm);
}

TEST_F(GlFftTest, ForwardMatchesFftwDouble) {
  for (const int n : {64, 128, 256, 512}) {
    gl::GlFft fft(n, n);
    const auto input = random_grid(fft.element_count(), static_cast<std::uint64_t>(n));
    fft.upload(input);
    fft.transform(gl::FftDirection::forward);
    const double error = relative_l2(fft.download(), fftw_2d(input, n, n, FFTW_FORWARD));
    std::ostringstream figure;
    figure << error;
    RecordProperty("forward_relative_l2_" + std::to_string(n), figure.str());
    EXPECT_LE(error, 1e-5) << "N = " << n;
  }
}

TEST_F(GlFftTest, InverseMatchesFftwDoubleScaled) {
  const int n = 256;
  gl::GlFft fft(n, n);
  const auto input = random_grid(fft.element_count(), 7);
  fft.upload(input);
  fft.transform(gl::FftDirection::inverse);
  auto expected = fftw_2d(input, n, n, FFTW_BACKWARD);
  for (auto& value : expected) value /= static_cast<double>(n) * n;
  EXPECT_LE(relative_l2(fft.download(), expected), 1e-5);
}

TEST_F(GlFftTest, RectangularBatchedMatchesFftwPerLayer) {
  const int width = 128, height = 32, layers = 3;
  gl::GlFft fft(width, height, layers);
  const auto input = random_grid(fft.element_count(), 11);
  fft.upload(input);
  fft.transform(gl::FftDirection::forward);
  const auto output = fft.download();
  const std::size_t layer_size = static_cast<std::size_t>(width) * height;
  for (int layer = 0; layer < layers; ++layer) {
    const auto begin = static_cast<std::ptrdiff_t>(layer * layer_size);
    const std::vector<std::complex<float>> in(input.begin() + begin, input.begin() + begin + static_cast<std::ptrdiff_t>(layer_size));
    const std::vector<std::complex<float>> out(output.begin() + begin, output.begin() + begin + static_cast<std::ptrdiff_t>(layer_size));
    EXPECT_LE(relative_l2(out, fftw_2d(in, width, height, FFTW_FORWARD)), 1e-5) << "layer " << layer;
  }
}

TEST_F(GlFftTest, ParsevalAndRoundTrip) {
  for (const int n : {64, 512}) {
    gl::GlFft fft(n, n);
    const auto input = random_grid(fft.element_count(), 100 + static_cast<std::uint64_t>(n));
    fft.upload(input);
    fft.transform(gl::FftDirection::forward);
    const auto spectrum = fft.download();
    double energy = 0.0, spectral_energy = 0.0;
    for (std::size_t i = 0; i < input.size(); ++i) {
      energy += std::norm(Complex(input[i]));
      spectral_energy += std::norm(Complex(spectrum[i]));
    }
    // Parseval for the unnormalised DFT: sum |X|^2 = N^2 sum |x|^2.
    EXPECT_NEAR(spectral_energy / (static_cast<double>(n) * n) / energy, 1.0, 1e-5) << "N = " << n;

    fft.transform(gl::FftDirection::inverse);
    const std::vector<Complex> expected(input.begin(), input.end());
    EXPECT_LE(relative_l2(fft.download(), expected), 1e-5) << "N = " << n;
  }
}

// Lengths of 2s, 3s and 5s (a padded grid fitted to its frame), each against FFTW in double: every
// radix alone and mixed, a line of 3^7 alone in its workgroup, lines of 16 by the hundred, several
// layers, forward and inverse.
TEST_F(GlFftTest, MixedRadixLengthsMatchFftwDouble) {
  struct Case {
    int width, height, layers;
  };
  for (const Case c : {Case{48, 80, 1}, Case{360, 54, 3}, Case{2187, 16, 1}, Case{16, 1125, 1}, Case{1350, 20, 2},
                       Case{32, 18, 1}}) {
    SCOPED_TRACE(std::to_string(c.width) + " x " + std::to_string(c.height) + " x " + std::to_string(c.layers));
    gl::GlFft fft(c.width, c.height, c.layers);
    const auto input = random_grid(fft.element_count(), static_cast<std::uint64_t>(c.width * 7 + c.height));
    fft.upload(input);
    fft.transform(gl::FftDirection::forward);
    const auto output = fft.download();
    const std::size_t layer_size = static_cast<std::size_t>(c.width) * c.height;
    for (int layer = 0; layer < c.layers; ++layer) {
      const auto begin = static_cast<std::ptrdiff_t>(layer * layer_size), end = begin + static_cast<std::ptrdiff_t>(layer_size);
      const std::vector<std::complex<float>> in(input.begin() + begin, input.begin() + end);
      const std::vector<std::complex<float>> out(output.begin() + begin, output.begin() + end);
      EXPECT_LE(relative_l2(out, fftw_2d(in, c.width, c.height, FFTW_FORWARD)), 1e-5) << "layer " << layer;
    }
    fft.transform(gl::FftDirection::inverse);
    EXPECT_LE(relative_l2(fft.download(), std::vector<Complex>(input.begin(), input.end())), 1e-5) << "round trip";
  }
}

TEST_F(GlFftTest, RadicesAreFoursThenATwoThenThreesAndFives) {
  EXPECT_EQ(gl::fft_radices(4096), (std::vector<int>{4, 4, 4, 4, 4, 4}));
  EXPECT_EQ(gl::fft_radices(2048), (std::vector<int>{4, 4, 4, 4, 4, 2}));
  EXPECT_EQ(gl::fft_radices(1350), (std::vector<int>{2, 3, 3, 3, 5, 5}));
  EXPECT_EQ(gl::fft_radices(2187), (std::vector<int>(7, 3)));
  EXPECT_EQ(gl::fft_radices(960), (std::vector<int>{4, 4, 4, 3, 5}));
  EXPECT_TRUE(gl::fft_radices(1001).empty());
  EXPECT_TRUE(gl::fft_radices(8).empty());
}

TEST_F(GlFftTest, RefusesUnsupportedSizes) {
  for (const int bad : {0, 8, 112, 1001, 4097, 8192}) {
    EXPECT_THROW(gl::GlFft(bad, 256), std::invalid_argument) << bad;
    EXPECT_THROW(gl::GlFft(256, bad), std::invalid_argument) << bad;
  }
  try {
    gl::GlFft fft(1001, 256);
    FAIL() << "a width of 1001 (7 x 11 x 13) was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("width 1001 is not a product of 2s, 3s and 5s"), std::string::npos)
        << error.what();
  }
  EXPECT_TRUE(gl::is_supported_fft_length(4096));
  EXPECT_TRUE(gl::is_supported_fft_length(2187));
  EXPECT_FALSE(gl::is_supported_fft_length(4097));
  EXPECT_FALSE(gl::is_supported_fft_length(14));
  // The GL PSF's grids stay powers of two.
  EXPECT_TRUE(gl::is_power_of_two_fft_length(1024));
  EXPECT_FALSE(gl::is_power_of_two_fft_length(1350));
}

}  // namespace
}  // namespace glarelab
