// Sanitising an HDR image before convolution: counts of what changed, the stated cap, and the
// repaired image accepted by both backends. The sample image with planted NaN and Inf is from the
// OpenEXR test images (../shared/data/openexr-images).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <stdexcept>

#include "glare/cpu/backend.h"
#include "glare/image_sanitiser.h"
#include "core/exr_io.h"

namespace glarelab {
namespace {

TEST(GlareImageSanitiser, SyntheticImageCountsAndRepairs) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  ImageRGBA image(5, 3, 1.0f);
  image.pixel(0, 0)[0] = nan;
  image.pixel(0, 0)[2] = nan;  // two values, one pixel
  image.pixel(1, 0)[1] = inf;
  image.pixel(2, 1)[0] = -0.5f;
  image.pixel(3, 1)[2] = -inf;
  image.pixel(4, 2)[1] = 250.0f;  // the largest finite value
  image.pixel(4, 2)[3] = nan;     // alpha is not R, G, B: left alone
  SanitiseReport report;
  const ImageRGBA out = sanitise_image(image, {}, &report);
  EXPECT_EQ(report.nan_values, 2u);
  EXPECT_EQ(report.positive_infinity_values, 1u);
  EXPECT_EQ(report.negative_values, 2u);
  EXPECT_EQ(report.changed_pixels, 4u);
  EXPECT_EQ(report.infinity_cap, 250.0);
  EXPECT_EQ(out.pixel(0, 0)[0], 0.0f);
  EXPECT_EQ(out.pixel(0, 0)[1], 1.0f);
  EXPECT_EQ(out.pixel(1, 0)[1], 250.0f);
  EXPECT_EQ(out.pixel(2, 1)[0], 0.0f);
  EXPECT_EQ(out.pixel(3, 1)[2], 0.0f);
  EXPECT_TRUE(std::isnan(out.pixel(4, 2)[3]));
  EXPECT_NE(report.describe().find("2 NaN -> 0, 1 +Inf -> 250, 2 negative -> 0"), std::string::npos) << report.describe();

  SanitiseOptions capped;
  capped.positive_infinity_cap = 1e8;
  EXPECT_EQ(sanitise_image(image, capped).pixel(1, 0)[1], 1e8f);
  capped.positive_infinity_cap = -1.0;
  EXPECT_THROW(sanitise_image(image, capped), std::invalid_argument);

  // The backend refuses the raw image and accepts the repaired one.
  Psf delta;
  delta.size_px = 3;
  delta.degrees_per_pixel = 0.1;
  delta.values = {0, 0, 0, 0, 1, 0, 0, 0, 0};
  CpuGlareBackend cpu;
  EXPECT_THROW(cpu.convolve(image, delta), std::invalid_argument);
  const ImageRGBA convolved = cpu.convolve(out, delta);
  for (std::size_t k = 0; k < out.rgba.size(); ++k)
    if (k % 4 != 3) {
      EXPECT_NEAR(convolved.rgba[k], out.rgba[k], 1e-4) << k;
    }
}

TEST(GlareImageSanitiser, BrightRingsNanInfSampleImage) {
  const std::filesystem::path file =
      std::filesystem::path(GLARELAB_SOURCE_DIR) / "../shared/data/openexr-images/TestImages_BrightRingsNanInf.exr";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is not present (the shared OpenEXR sample images)";
  const ImageRGBA image = read_exr(file.string()).image;
  // Independent count of what the file holds.
  std::size_t nans = 0, infinities = 0, negatives = 0;
  float largest = 0.0f;
  for (std::size_t k = 0; k < image.rgba.size(); ++k) {
    if (k % 4 == 3) continue;
    const float v = image.rgba[k];
    if (std::isnan(v)) ++nans;
    else if (std::isinf(v) && v > 0) ++infinities;
    else if (v < 0) ++negatives;
    else largest = std::max(largest, v);
  }
  ASSERT_GT(nans, 0u);
  ASSERT_GT(infinities, 0u);
  SanitiseReport report;
  const ImageRGBA out = sanitise_image(image, {}, &report);
  std::cout << "TestImages_BrightRingsNanInf.exr: " << report.describe() << "\n";
  EXPECT_EQ(report.nan_values, nans);
  EXPECT_EQ(report.positive_infinity_values, infinities);
  EXPECT_EQ(report.negative_values, negatives);
  EXPECT_EQ(report.infinity_cap, static_cast<double>(largest));
  EXPECT_TRUE(inspect_pixels(out).clean()) << inspect_pixels(out).describe();
  // Every value that was fine is untouched.
  for (std::size_t k = 0; k < image.rgba.size(); ++k)
    if (k % 4 == 3 || (std::isfinite(image.rgba[k]) && image.rgba[k] >= 0)) {
      ASSERT_EQ(out.rgba[k], image.rgba[k]) << k;
    }
}

}  // namespace
}  // namespace glarelab
