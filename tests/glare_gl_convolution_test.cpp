// GPU convolution against a direct O(n^2 k^2) CPU convolution in double, a delta image, and the
// dynamic-range hard case: a 1e8 cd/m2 pixel beside a 1e-2 cd/m2 background.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "runner/display/compute_context.h"
#include "glare/gl/convolution.h"
#include "core/random.h"

namespace glarelab {
namespace {

class GlConvolutionTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = gl::create_compute_context(); }
  static void TearDownTestSuite() { context_.reset(); }
  static std::unique_ptr<DisplayBackend> context_;
};
std::unique_ptr<DisplayBackend> GlConvolutionTest::context_;

std::string figure(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// out(x, y) = sum_{u, v} image(x - (u - k/2), y - (v - k/2)) psf(u, v), zero outside the image.
std::vector<double> direct_convolution(const ImageRGBA& image, const Psf& psf) {
  const int w = image.width_px, h = image.height_px, k = psf.size_px;
  std::vector<double> out(3 * static_cast<std::size_t>(w) * h, 0.0);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double sum = 0.0;
        for (int v = 0; v < k; ++v)
          for (int u = 0; u < k; ++u) {
            const int sx = x - (u - k / 2), sy = y - (v - k / 2);
            if (sx < 0 || sy < 0 || sx >= w || sy >= h) continue;
            sum += double(image.pixel(sx, sy)[c]) * psf.at(psf.channels == 1 ? 0 : c, u, v);
          }
        out[(static_cast<std::size_t>(c) * h + y) * w + x] = sum;
      }
  return out;
}

Psf random_psf(int size, int channels, std::uint64_t seed) {
  const CounterRandom random(seed, RandomStream::glare_gl_test_input);
  Psf psf{size, 0.01, channels, std::vector<double>(static_cast<std::size_t>(channels) * size * size)};
  for (int c = 0; c < channels; ++c) {
    double sum = 0.0;
    for (int i = 0; i < size * size; ++i) sum += psf.values[static_cast<std::size_t>(c * size * size + i)] = random.uniform(static_cast<std::uint64_t>(i), static_cast<std::uint32_t>(c));
    for (int i = 0; i < size * size; ++i) psf.values[static_cast<std::size_t>(c * size * size + i)] /= sum;
  }
  return psf;
}

// A glare-like PSF: a narrow core and a 1/r^3 tail (the envelope of an Airy pattern), unit sum.
Psf core_and_tail_psf(int size) {
  Psf psf{size, 0.01, 3, std::vector<double>(3 * static_cast<std::size_t>(size) * size)};
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const double r = std::hypot(x - size / 2, y - size / 2);
        sum += psf.at(c, x, y) = std::exp(-r * r / (2.0 * (1.0 + 0.3 * c))) + 1e-3 / (1.0 + r * r * r);
      }
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) psf.at(c, x, y) /= sum;
  }
  return psf;
}

double relative_l2(const ImageRGBA& actual, const std::vector<double>& expected) {
  const std::size_t plane = static_cast<std::size_t>(actual.width_px) * actual.height_px;
  double error = 0.0, norm = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < actual.height_px; ++y)
      for (int x = 0; x < actual.width_px; ++x) {
        const double e = expected[c * plane + static_cast<std::size_t>(y) * actual.width_px + x];
        error += (actual.pixel(x, y)[c] - e) * (actual.pixel(x, y)[c] - e);
        norm += e * e;
      }
  return std::sqrt(error / norm);
}

TEST_F(GlConvolutionTest, MatchesDirectDoubleConvolution) {
  const CounterRandom random(21, RandomStream::glare_gl_test_input);
  ImageRGBA image(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      for (int c = 0; c < 4; ++c) image.pixel(x, y)[c] = static_cast<float>(100.0 * random.uniform(static_cast<std::uint64_t>(y * 40 + x), static_cast<std::uint32_t>(c)));
  gl::GlConvolution convolution;
  for (const int channels : {1, 3}) {
    const Psf psf = random_psf(15, channels, 5);
    gl::GlConvolutionReport report;
    const ImageRGBA result = convolution.convolve(image, psf, {}, &report);
    EXPECT_EQ(report.padded_width_px, 54);   // 40 + 14 -> 2 x 3^3 (the powers of two would take 64)
    EXPECT_EQ(report.padded_height_px, 45);  // 30 + 14 -> 3^2 x 5
    EXPECT_FALSE(report.split);
    const double error = relative_l2(result, direct_convolution(image, psf));
    RecordProperty("direct_relative_l2_channels_" + std::to_string(channels), figure(error));
    EXPECT_LE(error, 1e-4) << channels << " PSF channel(s)";
    EXPECT_EQ(result.pixel(3, 4)[3], image.pixel(3, 4)[3]) << "alpha passes through";
    EXPECT_FALSE(report.psf_spectrum_reused);
  }
  // The same PSF again with another image: its spectrum is reused and the result still exact.
  const Psf psf = random_psf(15, 3, 5);
  ImageRGBA second(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      for (int c = 0; c < 3; ++c) second.pixel(x, y)[c] = static_cast<float>(random.uniform(static_cast<std::uint64_t>(5000 + y * 40 + x), static_cast<std::uint32_t>(c)));
  gl::GlConvolutionReport report;
  const ImageRGBA result = convolution.convolve(second, psf, {}, &report);
  EXPECT_TRUE(report.psf_spectrum_reused) << report.describe();
  EXPECT_LE(relative_l2(result, direct_convolution(second, psf)), 1e-4);
  Psf changed = psf;
  changed.values[7] *= 2.0;
  const ImageRGBA changed_result = convolution.convolve(second, changed, {}, &report);
  EXPECT_FALSE(report.psf_spectrum_reused);
  EXPECT_LE(relative_l2(changed_result, direct_convolution(second, changed)), 1e-4);
}

TEST_F(GlConvolutionTest, DeltaImageGivesBackThePsf) {
  const Psf psf = core_and_tail_psf(31);
  ImageRGBA image(50, 45);
  image.pixel(20, 25)[0] = image.pixel(20, 25)[1] = image.pixel(20, 25)[2] = 1.0f;
  gl::GlConvolution convolution;
  const ImageRGBA result = convolution.convolve(image, psf, {.split_bright = false});
  double worst = 0.0, peak = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int v = 0; v < 31; ++v)
      for (int u = 0; u < 31; ++u) {
        peak = std::max(peak, psf.at(c, u, v));
        worst = std::max(worst, std::abs(result.pixel(20 + u - 15, 25 + v - 15)[c] - psf.at(c, u, v)));
      }
  RecordProperty("delta_max_error_over_peak", figure(worst / peak));
  EXPECT_LE(worst / peak, 1e-5);
  EXPECT_LE(std::abs(result.pixel(49, 0)[1]), 1e-5 * peak) << "nothing outside the PSF's reach";

  // A source in the corner: its PSF is cut at the edges, and nothing wraps to the far sides.
  ImageRGBA corner(50, 45);
  corner.pixel(0, 0)[0] = corner.pixel(0, 0)[1] = corner.pixel(0, 0)[2] = 1.0f;
  const ImageRGBA cut = convolution.convolve(corner, psf, {.split_bright = false});
  double worst_inside = 0.0, worst_far = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < 45; ++y)
      for (int x = 0; x < 50; ++x) {
        const double expected = x <= 15 && y <= 15 ? psf.at(c, x + 15, y + 15) : 0.0;
        (x <= 15 && y <= 15 ? worst_inside : worst_far) =
            std::max(x <= 15 && y <= 15 ? worst_inside : worst_far, std::abs(cut.pixel(x, y)[c] - expected));
      }
  EXPECT_LE(worst_inside / peak, 1e-5);
  EXPECT_LE(worst_far / peak, 1e-5) << "the PSF wrapped around an image edge";
}

TEST_F(GlConvolutionTest, SunBesideDimBackgroundStaysAccurateWhenSplit) {
  const int w = 96, h = 64;
  ImageRGBA image(w, h, 1e-2f);
  for (int c = 0; c < 3; ++c) image.pixel(20, 30)[c] = 1e8f;
  const Psf psf = core_and_tail_psf(63);
  const std::vector<double> expected = direct_convolution(image, psf);
  const std::size_t plane = static_cast<std::size_t>(w) * h;
  // Dim region: where the exact result is below 10 x the background.
  const auto dim_error = [&](const ImageRGBA& result) {
    double worst = 0.0;
    int count = 0;
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const double e = expected[c * plane + static_cast<std::size_t>(y) * w + x];
          if (e >= 0.1) continue;
          ++count;
          worst = std::max(worst, std::abs(result.pixel(x, y)[c] - e) / e);
        }
    EXPECT_GT(count, 1000);
    return worst;
  };
  gl::GlConvolution convolution;
  gl::GlConvolutionReport report;
  const double unsplit = dim_error(convolution.convolve(image, psf, {.split_bright = false}));
  const ImageRGBA split_result = convolution.convolve(image, psf, {}, &report);
  const double split = dim_error(split_result);
  RecordProperty("dim_region_max_relative_error_unsplit", figure(unsplit));
  RecordProperty("dim_region_max_relative_error_split", figure(split));
  EXPECT_TRUE(report.split) << report.describe();
  EXPECT_EQ(report.bright_pixels, 1u);
  EXPECT_GT(unsplit, 1e-2) << "the hard case must be hard for a plain float32 FFT";
  EXPECT_LT(split, 1e-2);
  EXPECT_LE(relative_l2(split_result, expected), 1e-5);
}

// The GPU's pad pass leaves out the pixels the host summed directly, by a float comparison against
// a double threshold: a pixel just above the threshold whose nearest float lies above it too must be
// counted once (directly), and one just below it once (by FFT), never twice or not at all.
TEST_F(GlConvolutionTest, PixelsBesideTheSplitThresholdAreCountedOnce) {
  // A dynamic range whose threshold (x the median, 1) rounds up to the nearest float: rounding the
  // threshold to nearest on the GPU would put the pixel at that float in both parts.
  double range = 0.0;
  for (int n = 1; n < 64 && range == 0.0; ++n) {
    const double candidate = 1e4 + n / 3.0;
    if (static_cast<double>(static_cast<float>(candidate)) > candidate) range = candidate;
  }
  ASSERT_GT(range, 0.0);
  const float above = static_cast<float>(range);  // the float nearest the threshold, above it
  const float below = std::nextafter(above, 0.0f);
  ASSERT_LT(static_cast<double>(below), range);
  ImageRGBA image(48, 40, 1.0f);
  for (int c = 0; c < 3; ++c) {
    image.pixel(10, 12)[c] = above;
    image.pixel(30, 25)[c] = below;
  }
  const Psf psf = core_and_tail_psf(21);
  gl::GlConvolution convolution;
  gl::GlConvolutionReport report;
  const ImageRGBA result = convolution.convolve(image, psf, {.split_dynamic_range = range}, &report);
  EXPECT_TRUE(report.split) << report.describe();
  EXPECT_EQ(report.bright_pixels, 1u) << report.describe();
  // Counted twice or left out, the pixel at `above` would move the result by about its own
  // value times the PSF, near 1 of the ~1e4 energy: a relative L2 far above float rounding.
  EXPECT_LE(relative_l2(result, direct_convolution(image, psf)), 1e-5);
  EXPECT_GT(report.gpu_s, 0.0) << "the GPU's time is measured";
}

// The direct sum runs only over the bright pixels' box grown by the PSF's reach, which is not the
// same on both sides for an even PSF size: a random (asymmetric) 20 px PSF and two bright pixels
// inside the image check both sides against the direct double convolution. The grown box is 57 px
// (2 to 58) each way, one more than 7 tiles of 8, so a box one pixel short on either side would
// leave the last row and column of it out instead of hiding in the last tile.
TEST_F(GlConvolutionTest, SplitSumReachesEveryPixelTheBrightPixelsLight) {
  ImageRGBA image(72, 64, 1.0f);
  for (int c = 0; c < 3; ++c) {
    image.pixel(12, 12)[c] = 1e5f;
    image.pixel(49, 49)[c] = 2e5f;
  }
  for (const int channels : {1, 3}) {
    const Psf psf = random_psf(20, channels, 11);
    gl::GlConvolution convolution;
    gl::GlConvolutionReport report;
    const ImageRGBA result = convolution.convolve(image, psf, {}, &report);
    EXPECT_TRUE(report.split) << report.describe();
    EXPECT_EQ(report.bright_pixels, 2u) << report.describe();
    EXPECT_LE(relative_l2(result, direct_convolution(image, psf)), 1e-5) << channels << " PSF channel(s)";
  }
}

// A caller that names its images (GlConvolutionOptions::image_token, a session's seen image through
// its FrameFacts) has the kept spectrum known by the name alone: the same token is the kept image,
// another token is another image, no token compares the pixels. Each result is a fresh
// convolution's, bit for bit.
TEST_F(GlConvolutionTest, ATokenNamesTheKeptImageWithoutItsPixels) {
  ImageRGBA scene(60, 44, 2.0f);
  for (int c = 0; c < 3; ++c) scene.pixel(17, 21)[c] = 3e5f;
  ImageRGBA changed = scene;
  changed.pixel(59, 43)[1] = 2.5f;
  const Psf psf = random_psf(15, 3, 23);
  struct Call {
    const ImageRGBA* image;
    std::uint64_t token;
    bool image_reused;
  };
  const std::vector<Call> calls = {{&scene, 5, false},  {&scene, 5, true},   {&changed, 6, false}, {&changed, 6, true},
                                   {&scene, 0, false},  {&scene, 0, true},   {&scene, 7, false},   {&scene, 7, true}};
  gl::GlConvolution kept;
  for (std::size_t n = 0; n < calls.size(); ++n) {
    gl::GlConvolutionOptions options;
    options.image_token = calls[n].token;
    gl::GlConvolutionReport report;
    const ImageRGBA result = kept.convolve(*calls[n].image, psf, options, &report);
    EXPECT_EQ(report.image_spectrum_reused, calls[n].image_reused) << "call " << n << ": " << report.describe();
    EXPECT_EQ(result.rgba, gl::GlConvolution().convolve(*calls[n].image, psf).rgba) << "call " << n;
  }
}

// Both spectra are kept from call to call: a frame of dynamic glare over a static scene transforms
// only its new PSF, one of static glare nothing. Whatever is kept, each result must be the one a
// fresh convolution gives for the same image and PSF, bit for bit, and a change anywhere in the image
// (its last pixel here), in its split or in the PSF must be noticed.
TEST_F(GlConvolutionTest, KeptSpectraGiveTheResultsOfAFreshConvolution) {
  ImageRGBA scene(60, 44, 2.0f);
  for (int c = 0; c < 3; ++c) scene.pixel(17, 21)[c] = 3e5f;
  ImageRGBA changed = scene;
  changed.pixel(59, 43)[1] = 2.5f;
  const Psf first = random_psf(15, 3, 21), second = random_psf(15, 3, 22);
  struct Call {
    const ImageRGBA* image;
    const Psf* psf;
    gl::GlConvolutionOptions options;
    bool image_reused, psf_reused;
  };
  const std::vector<Call> calls = {
      {&scene, &first, {}, false, false},   {&scene, &second, {}, true, false},
      {&scene, &second, {}, true, true},    {&changed, &second, {}, false, true},
      {&scene, &first, {}, false, false},   {&scene, &first, {.split_bright = false}, false, true},
      {&scene, &first, {.split_bright = false}, true, true},
  };
  gl::GlConvolution kept;
  for (std::size_t n = 0; n < calls.size(); ++n) {
    const Call& call = calls[n];
    gl::GlConvolutionReport report;
    const ImageRGBA result = kept.convolve(*call.image, *call.psf, call.options, &report);
    EXPECT_EQ(report.image_spectrum_reused, call.image_reused) << "call " << n << ": " << report.describe();
    EXPECT_EQ(report.psf_spectrum_reused, call.psf_reused) << "call " << n << ": " << report.describe();
    EXPECT_EQ(report.split, call.options.split_bright) << "call " << n << ": " << report.describe();
    gl::GlConvolution fresh;
    const ImageRGBA expected = fresh.convolve(*call.image, *call.psf, call.options);
    EXPECT_EQ(result.rgba, expected.rgba) << "call " << n;
    EXPECT_LE(relative_l2(result, direct_convolution(*call.image, *call.psf)), 1e-5) << "call " << n;
  }
  // A refused image leaves the kept spectra as they were.
  ImageRGBA refused = scene;
  refused.pixel(3, 3)[0] = -1.0f;
  EXPECT_THROW(kept.convolve(refused, second, {.split_bright = false}), std::invalid_argument);
  gl::GlConvolutionReport report;
  const ImageRGBA after_refusal = kept.convolve(scene, first, {.split_bright = false}, &report);
  EXPECT_TRUE(report.image_spectrum_reused && report.psf_spectrum_reused) << report.describe();
  EXPECT_EQ(after_refusal.rgba, gl::GlConvolution().convolve(scene, first, {.split_bright = false}).rgba);
  kept.forget_image();
  (void)kept.convolve(scene, first, {.split_bright = false}, &report);
  EXPECT_FALSE(report.image_spectrum_reused) << "forget_image() drops the kept spectrum";
}

TEST_F(GlConvolutionTest, RefusesBadInput) {
  gl::GlConvolution convolution;
  const Psf psf = random_psf(5, 1, 1);
  EXPECT_THROW(convolution.convolve(ImageRGBA{}, psf), std::invalid_argument);
  ImageRGBA image(8, 8, 1.0f);
  image.pixel(2, 2)[1] = std::nanf("");
  image.pixel(3, 2)[0] = -1.0f;
  try {
    convolution.convolve(image, psf);
    FAIL() << "NaN and negative pixels were accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("GL convolution"), std::string::npos) << error.what();
  }
  Psf broken = psf;
  broken.values.pop_back();
  EXPECT_THROW(convolution.convolve(ImageRGBA(8, 8, 1.0f), broken), std::invalid_argument);
  EXPECT_THROW(convolution.convolve(ImageRGBA(4000, 8, 1.0f), random_psf(201, 1, 2)), std::invalid_argument);
  EXPECT_EQ(gl::padded_fft_length(1), 16);
  EXPECT_EQ(gl::padded_fft_length(4096), 4096);
  EXPECT_EQ(gl::padded_fft_length(17), 18);      // 2 x 3 x 3
  EXPECT_EQ(gl::padded_fft_length(1335), 1350);  // 1080 + 256 - 1: 2 x 3^3 x 5^2
  EXPECT_EQ(gl::padded_fft_length(2175), 2187);  // 1920 + 256 - 1: 3^7
  EXPECT_EQ(gl::padded_fft_length(4097), 0);
}

}  // namespace
}  // namespace glarelab
