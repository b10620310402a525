// The glare stage: control passes frames through bit-identically, a static eye gives the same
// frame at every time, a dynamic eye changes over time but is reproducible from (seed, time), the
// convolution conserves each channel's energy, and skipping glare on invisible frames costs at most
// the visibility threshold (measured against the convolution it skipped).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "glare/convolution_cpu.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

GlareSpec small_spec() {
  GlareSpec spec;
  spec.grid_px = 128;  // PSF 128 px of lambda / 10 mm = 0.0033 deg: 17 display pixels across
  spec.wavelength_samples = 8;
  return spec;
}

DisplaySpec small_display() {
  DisplaySpec display;
  display.width_px = 96;
  display.height_px = 64;
  return display;
}

// A uniform surround with a bright square in the middle, far from the edges.
ImageRGBA lamp_frame(float surround_cd_m2, float lamp_cd_m2) {
  ImageRGBA frame(96, 64, surround_cd_m2);
  for (int y = 28; y < 36; ++y)
    for (int x = 44; x < 52; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = lamp_cd_m2;
  return frame;
}

double channel_sum(const ImageRGBA& image, int channel) {
  double sum = 0.0;
  for (std::size_t i = static_cast<std::size_t>(channel); i < image.rgba.size(); i += 4) sum += image.rgba[i];
  return sum;
}

// max_x |a(x) - b(x)| / max(Y_b(x), floor) over the luminance Y.
double max_relative_change(const ImageRGBA& changed, const ImageRGBA& original, double floor_cd_m2) {
  double worst = 0.0;
  for (std::size_t i = 0; i < original.rgba.size(); i += 4) {
    const double before = luminance_rec709(original.rgba[i], original.rgba[i + 1], original.rgba[i + 2]);
    const double after = luminance_rec709(changed.rgba[i], changed.rgba[i + 1], changed.rgba[i + 2]);
    worst = std::max(worst, std::abs(after - before) / std::max(before, floor_cd_m2));
  }
  return worst;
}

TEST(GlareStage, ControlReturnsTheFrameBitIdentical) {
  GlareStage stage(small_spec(), small_display(), 7);
  ImageRGBA frame = lamp_frame(0.5f, 200.0f);
  frame.pixel(3, 4)[1] = 1e-7f;  // values a round trip through any arithmetic would disturb
  frame.pixel(5, 6)[2] = 12345.678f;
  GlareFrameReport report;
  const ImageRGBA out = stage.apply(frame, GlareMode::control, 1.25, &report);
  EXPECT_EQ(out.rgba, frame.rgba);
  EXPECT_FALSE(report.convolved);
}

TEST(GlareStage, StaticEyeGivesTheSameFrameAtEveryTime) {
  GlareStage stage(small_spec(), small_display(), 7);
  const ImageRGBA frame = lamp_frame(0.5f, 200.0f);
  GlareFrameReport report;
  const ImageRGBA early = stage.apply(frame, GlareMode::static_eye, 0.1, &report);
  ASSERT_TRUE(report.convolved);
  const ImageRGBA late = stage.apply(frame, GlareMode::static_eye, 3.7, &report);
  EXPECT_EQ(early.rgba, late.rgba);
  EXPECT_NE(early.rgba, frame.rgba);  // and it is glare, not the frame
}

TEST(GlareStage, DynamicEyeChangesOverTimeAndIsReproducibleFromSeedAndTime) {
  const ImageRGBA frame = lamp_frame(0.5f, 200.0f);
  GlareStage first(small_spec(), small_display(), 11);
  GlareStage second(small_spec(), small_display(), 11);
  const ImageRGBA a = first.apply(frame, GlareMode::dynamic, 0.5);
  const ImageRGBA b = second.apply(frame, GlareMode::dynamic, 0.5);
  EXPECT_EQ(a.rgba, b.rgba);
  const ImageRGBA later = first.apply(frame, GlareMode::dynamic, 1.5);
  EXPECT_GT(max_relative_change(later, a, 0.5), 1e-4);
  GlareStage other_seed(small_spec(), small_display(), 12);
  EXPECT_NE(other_seed.apply(frame, GlareMode::dynamic, 0.5).rgba, a.rgba);
}

TEST(GlareStage, ConvolutionConservesEachChannelsEnergyWhenNothingLeavesTheFrame) {
  GlareStage stage(small_spec(), small_display(), 3);
  const ImageRGBA frame = lamp_frame(0.0f, 500.0f);  // black surround: nothing near the edges
  GlareFrameReport report;
  const ImageRGBA out = stage.apply(frame, GlareMode::dynamic, 0.2, &report);
  ASSERT_TRUE(report.convolved);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(channel_sum(out, c) / channel_sum(frame, c), 1.0, 1e-6) << "channel " << c;
  // Light spreads out of the lamp: its centre loses, the surround next to it gains.
  EXPECT_LT(out.pixel(47, 31)[1], 500.0f);
  EXPECT_GT(out.pixel(40, 31)[1], 0.0f);
}

TEST(GlareStage, VisibilityBoundHoldsAndSkippingAnInvisibleFrameCostsLessThanTheThreshold) {
  // A very dim frame (lamp 1e-4 cd/m2 on black): the skip is decided from the bound.
  GlareSpec spec = small_spec();
  GlareStage skipping(spec, small_display(), 5);
  const ImageRGBA dim = lamp_frame(0.0f, 1e-4f);
  GlareFrameReport report;
  const ImageRGBA skipped = skipping.apply(dim, GlareMode::static_eye, 0.0, &report);
  EXPECT_FALSE(report.convolved);
  EXPECT_FALSE(report.skip_reason.empty());
  EXPECT_EQ(skipped.rgba, dim.rgba);
  EXPECT_LT(report.visibility_bound, spec.visibility_weber_fraction);
  // The error of skipping: the same frame with the convolution done.
  spec.skip_invisible = false;
  GlareStage forced(spec, small_display(), 5);
  GlareFrameReport forced_report;
  const ImageRGBA glared = forced.apply(dim, GlareMode::static_eye, 0.0, &forced_report);
  ASSERT_TRUE(forced_report.convolved);
  const double error = max_relative_change(glared, dim, spec.visibility_floor_cd_m2);
  std::printf("skip error (dim frame): measured %.3g, bound %.3g, threshold %.3g, wing fraction %.3f\n", error,
              report.visibility_bound, spec.visibility_weber_fraction, report.wing_fraction);
  EXPECT_GT(error, 0.0);
  EXPECT_LE(error, report.visibility_bound * (1.0 + 1e-6));

  // A visible case: the bound still bounds the change, and the stage does not skip.
  const ImageRGBA bright = lamp_frame(1.0f, 200.0f);
  const ImageRGBA bright_glared = forced.apply(bright, GlareMode::static_eye, 0.0, &forced_report);
  const double bright_change = max_relative_change(bright_glared, bright, spec.visibility_floor_cd_m2);
  EXPECT_LE(bright_change, forced_report.visibility_bound * (1.0 + 1e-6));
  EXPECT_GT(bright_change, spec.visibility_weber_fraction);
  GlareFrameReport not_skipped;
  skipping.apply(bright, GlareMode::static_eye, 0.0, &not_skipped);
  EXPECT_TRUE(not_skipped.convolved);
}

TEST(GlareStage, FibreGratingsDropOutBehindASmallPupil) {
  // Moon and Spencer (Ritschel Eq. 2): D = 4.9 - 3 tanh(0.4 (log10 L + 1)) mm. A 2000 cd/m2 field
  // gives 2.09 mm, inside the clear lens centre (cortex annulus from 3 mm); 0.01 cd/m2 gives 6.04 mm.
  // Hippus (Eq. 1) adds at most 0.1 (9 / D) sqrt(1 - D / 9): 0.38 mm and 0.06 mm.
  GlareStage stage(small_spec(), small_display(), 9);
  GlareFrameReport bright, dark;
  stage.apply(ImageRGBA(96, 64, 2000.0f), GlareMode::static_eye, 0.0, &bright);
  stage.apply(ImageRGBA(96, 64, 0.01f), GlareMode::static_eye, 0.0, &dark);
  EXPECT_NEAR(bright.pupil_diameter_mm, 4.9 - 3.0 * std::tanh(0.4 * (std::log10(2000.0) + 1.0)), 0.38);
  EXPECT_NEAR(dark.pupil_diameter_mm, 4.9 - 3.0 * std::tanh(0.4 * (std::log10(0.01) + 1.0)), 0.07);
  EXPECT_FALSE(bright.gratings_in_pupil);
  EXPECT_TRUE(dark.gratings_in_pupil);
}

TEST(GlareStage, CroppedConvolutionEqualsTheWholeFrameConvolution) {
  // The stage convolves only the black-bordered region light can reach; the reference convolves
  // the whole frame with the same PSF.
  GlareStage stage(small_spec(), small_display(), 4);
  const ImageRGBA frame = lamp_frame(0.0f, 300.0f);
  const std::optional<Psf> psf = stage.display_psf(GlareMode::static_eye, 0.0, mean_luminance(frame));
  ASSERT_TRUE(psf.has_value());
  const ImageRGBA whole = convolve_image_cpu(frame, *psf, ConvolutionOptions{});
  const ImageRGBA cropped = stage.apply(frame, GlareMode::static_eye, 0.0);
  double worst = 0.0;
  for (std::size_t i = 0; i < whole.rgba.size(); ++i)
    worst = std::max(worst, static_cast<double>(std::abs(whole.rgba[i] - cropped.rgba[i])));
  EXPECT_LT(worst, 300.0 * 1e-6);
}

TEST(GlareStage, VisibilityBoundFormula) {
  // Spelled out: peak 100, wing 0.2 -> 20 cd/m2 of veil at most; against 10 cd/m2 -> 2.
  EXPECT_DOUBLE_EQ(visibility_bound(100.0, 10.0, 0.2, 0.01), 2.0);
  // Below the floor the floor is the reference.
  EXPECT_DOUBLE_EQ(visibility_bound(1.0, 0.0, 0.1, 0.5), 0.2);
}

}  // namespace
}  // namespace glarelab

