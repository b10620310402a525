// The analytic glare on images (glare/analytic/display_kernel_convolution.h, glare/analytic/analytic_glare.h): a
// point source convolved gives the PSF integrated per pixel, energy is what the kernel keeps on
// the frame, the planned float32 path agrees with the float64 reference, and a Spencer mixture
// made from component spectra equals the mixture's own kernel, and a frame brought again gets the
// kept glare.
#include <cmath>

#include <gtest/gtest.h>

#include "core/random.h"
#include "glare/analytic/analytic_glare.h"
#include "glare/analytic/display_kernel_convolution.h"

namespace glarelab {
namespace {

constexpr int kWidth = 48, kHeight = 36;

ImageRGBA black_frame() {
  ImageRGBA image(kWidth, kHeight);
  for (std::size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 1.0f;
  return image;
}

float& channel(ImageRGBA& image, int x, int y, int c) { return image.rgba[4 * (static_cast<std::size_t>(y) * kWidth + x) + c]; }

TEST(AnalyticConvolution, PointSourceGivesThePsfIntegratedPerPixel) {
  const AnalyticPsf psf = AnalyticPsf::spencer(SpencerRegime::scotopic, 0.0, ObserverEye{30.0, 0.5});
  const DisplayGeometry geometry{600.0, 0.25};
  const DisplayKernel kernel = analytic_display_kernel(psf, geometry, kWidth - 1, kHeight - 1, 2);
  ImageRGBA frame = black_frame();
  const int sx = 13, sy = 21;
  for (int c = 0; c < 3; ++c) channel(frame, sx, sy, c) = 1000.0f;
  const ImageRGBA exact = convolve_with_kernel_float64(frame, kernel);
  DisplayKernelConvolution planned(kWidth, kHeight, kWidth - 1, kHeight - 1, 2);
  planned.set_components({kernel});
  planned.set_weights({1.0});
  ImageRGBA fast;
  planned.convolve(frame, fast);
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0, expected_sum = 0.0, peak = 0.0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        // The reference is float64 inside, rounded to float on output: 1e-4 leaves room for nothing else.
        const double expected = 1000.0 * pixel_energy(psf, c, x - sx, y - sy, geometry);
        EXPECT_NEAR(channel(const_cast<ImageRGBA&>(exact), x, y, c), expected, 1e-4 * expected)
            << "channel " << c << " at " << x << ", " << y;
        sum += channel(fast, x, y, c);
        expected_sum += expected;
        peak = std::max(peak, expected);
      }
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        EXPECT_NEAR(channel(fast, x, y, c), channel(const_cast<ImageRGBA&>(exact), x, y, c), 1e-6 * peak);
    // Energy: what the kernel keeps on the frame around this source, no more, no less.
    EXPECT_NEAR(sum, expected_sum, 1e-6 * expected_sum) << "channel " << c;
  }
}

TEST(AnalyticConvolution, PlannedFloatPathAgreesWithFloat64OnAnHdrFrame) {
  const AnalyticPsf psf = AnalyticPsf::cie(ObserverEye{50.0, 0.8});
  const DisplayKernel kernel = analytic_display_kernel(psf, DisplayGeometry{}, kWidth - 1, kHeight - 1, 2);
  ImageRGBA frame = black_frame();
  const CounterRandom rng(7, RandomStream::glare_gl_test_input);  // test signals
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c)
        channel(frame, x, y, c) = static_cast<float>(100.0 * rng.uniform(static_cast<std::uint64_t>((y * kWidth + x) * 3 + c)));
  channel(frame, 30, 5, 1) = 1e5f;  // a lamp
  DisplayKernelConvolution planned(kWidth, kHeight, kWidth - 1, kHeight - 1, 1);
  planned.set_components({kernel});
  planned.set_weights({1.0});
  ImageRGBA fast;
  planned.convolve(frame, fast);
  const ImageRGBA exact = convolve_with_kernel_float64(frame, kernel);
  for (std::size_t i = 0; i < fast.rgba.size(); ++i) EXPECT_NEAR(fast.rgba[i], exact.rgba[i], 1e-6 * 1e5);
}

// Spencer's adaptive regime for a 40-year-old on the test's frames.
AnalyticGlareOptions adaptive_spencer_options() {
  AnalyticGlareOptions options;
  options.model = GlareModel::spencer;
  options.eye = ObserverEye{40.0, 0.5};
  options.width_px = kWidth;
  options.height_px = kHeight;
  options.regime = SpencerRegime::adaptive;
  return options;
}

TEST(AnalyticConvolution, AdaptiveMixtureFromComponentSpectraEqualsTheRegimesOwnKernel) {
  AnalyticGlareOptions options = adaptive_spencer_options();
  AnalyticGlare adaptive(options, 2);
  options.regime = SpencerRegime::scotopic;
  AnalyticGlare scotopic(options, 2);
  adaptive.adapt(0.001);  // deep in the scotopic band
  const DisplayKernel a = adaptive.current_kernel(), b = scotopic.current_kernel();
  ASSERT_EQ(a.values.size(), b.values.size());
  for (std::size_t i = 0; i < a.values.size(); ++i) EXPECT_NEAR(a.values[i], b.values[i], 1e-12 + 1e-9 * b.values[i]);
  ImageRGBA frame = black_frame(), out_a, out_b;
  channel(frame, 20, 10, 0) = 500.0f;
  channel(frame, 5, 30, 2) = 80.0f;
  adaptive.convolve(frame, out_a);
  scotopic.convolve(frame, out_b);
  for (std::size_t i = 0; i < out_a.rgba.size(); ++i) EXPECT_NEAR(out_a.rgba[i], out_b.rgba[i], 2e-6 * 500.0);
  // A brighter field moves the mixture to photopic: no halo weight left.
  adaptive.adapt(100.0);
  EXPECT_EQ(adaptive.mixture().f3, 0.0);
}

// A frame brought again under the same kernel gets the kept glare, bit for bit what a new engine
// computes; a changed pixel or a moved mixture computes anew.
TEST(AnalyticConvolution, AFrameBroughtAgainGetsTheKeptGlareAndAChangedOneANewConvolution) {
  AnalyticGlareOptions options = adaptive_spencer_options();
  AnalyticGlare engine(options, 2);
  ImageRGBA frame = black_frame(), first, again;
  channel(frame, 20, 10, 1) = 500.0f;
  engine.adapt(100.0);
  engine.convolve(frame, first);
  engine.convolve(frame, again);
  EXPECT_EQ(engine.convolutions_computed(), 1);
  EXPECT_EQ(again.rgba, first.rgba);

  const auto fresh = [&](const ImageRGBA& source, double adaptation_cd_m2) {
    AnalyticGlare other(options, 2);
    other.adapt(adaptation_cd_m2);
    ImageRGBA out;
    other.convolve(source, out);
    return out;
  };
  channel(frame, 30, 20, 0) = 7.0f;  // one pixel changed
  ImageRGBA changed;
  engine.convolve(frame, changed);
  EXPECT_EQ(engine.convolutions_computed(), 2);
  EXPECT_EQ(changed.rgba, fresh(frame, 100.0).rgba);
  EXPECT_NE(changed.rgba, first.rgba);

  engine.adapt(0.001);  // scotopic: the halo's weight, a new kernel
  ImageRGBA scotopic;
  engine.convolve(frame, scotopic);
  EXPECT_EQ(engine.convolutions_computed(), 3);
  EXPECT_EQ(scotopic.rgba, fresh(frame, 0.001).rgba);
}

}  // namespace
}  // namespace glarelab
