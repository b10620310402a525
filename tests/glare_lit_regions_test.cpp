// glare/cpu/lit_regions.h: the boxes around a frame's lit pixels, checked on hand-drawn frames whose
// boxes are known by construction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "glare/cpu/lit_regions.h"

namespace glarelab {
namespace {

void light(ImageRGBA& image, const PixelRect& box, int channel = 1, float value = 1.0f) {
  for (int y = box.y_px; y < box.y_px + box.height_px; ++y)
    for (int x = box.x_px; x < box.x_px + box.width_px; ++x) image.pixel(x, y)[channel] = value;
}

std::vector<PixelRect> sorted(std::vector<PixelRect> boxes) {
  std::sort(boxes.begin(), boxes.end(),
            [](const PixelRect& a, const PixelRect& b) { return a.x_px != b.x_px ? a.x_px < b.x_px : a.y_px < b.y_px; });
  return boxes;
}

TEST(LitRegions, TheDemoLayoutGivesOneTightBoxPerRoom) {
  // Two 256 px rooms 256 px apart on a 1024 x 512 display, off the 8 px tile grid by 3 and 5 px.
  ImageRGBA frame(1024, 512, 0.0f);
  const PixelRect left{131, 125, 256, 256}, right{643, 131, 250, 256};
  light(frame, left);
  light(frame, right, 0, 0.25f);
  frame.pixel(700, 300)[3] = 1.0f;  // alpha alone is not light
  const std::vector<PixelRect> boxes = sorted(lit_regions(frame, 38));
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_EQ(boxes[0], left);
  EXPECT_EQ(boxes[1], right);
}

TEST(LitRegions, GapsNarrowerThanTheCutAreKeptInOneBox) {
  ImageRGBA frame(200, 100, 0.0f);
  light(frame, PixelRect{10, 10, 40, 30});
  light(frame, PixelRect{70, 20, 40, 50});  // 20 px of black between them: fewer than 38
  const std::vector<PixelRect> together = lit_regions(frame, 38);
  ASSERT_EQ(together.size(), 1u);
  EXPECT_EQ(together[0], (PixelRect{10, 10, 100, 60}));
  // The same gap is cut when the PSF is narrower than it (one whole empty 8 px tile lies in it).
  EXPECT_EQ(lit_regions(frame, 8).size(), 2u);
}

TEST(LitRegions, CutsRowsInsideAColumnAndEverySplitIsWideEnough) {
  // An L-shaped layout: a tall box on the left; on the right two boxes one above the other.
  ImageRGBA frame(300, 300, 0.0f);
  const PixelRect tall{5, 5, 40, 290}, upper{120, 10, 60, 60}, lower{130, 200, 100, 90};
  light(frame, tall);
  light(frame, upper, 2);
  light(frame, lower);
  const int gap_px = 50;
  const std::vector<PixelRect> boxes = sorted(lit_regions(frame, gap_px));
  ASSERT_EQ(boxes.size(), 3u);
  EXPECT_EQ(boxes[0], tall);
  EXPECT_EQ(boxes[1], upper);
  EXPECT_EQ(boxes[2], lower);
  // Every lit pixel is in a box, and boxes are at least gap_px apart along x or y.
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 300; ++x) {
      const float* p = frame.pixel(x, y);
      if (p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f) continue;
      EXPECT_TRUE(std::any_of(boxes.begin(), boxes.end(), [&](const PixelRect& b) {
        return x >= b.x_px && x < b.x_px + b.width_px && y >= b.y_px && y < b.y_px + b.height_px;
      }));
    }
  for (std::size_t a = 0; a < boxes.size(); ++a)
    for (std::size_t b = a + 1; b < boxes.size(); ++b) {
      const int gap_x = std::max(boxes[b].x_px - boxes[a].right_px(), boxes[a].x_px - boxes[b].right_px());
      const int gap_y = std::max(boxes[b].y_px - boxes[a].bottom_px(), boxes[a].y_px - boxes[b].bottom_px());
      EXPECT_GE(std::max(gap_x, gap_y), gap_px);
    }
}

TEST(LitRegions, BlackNegativeZeroNanAndTooManyLights) {
  ImageRGBA frame(64, 64, 0.0f);
  EXPECT_TRUE(lit_regions(frame, 8).empty());
  frame.pixel(5, 5)[0] = -0.0f;  // black too
  EXPECT_TRUE(lit_regions(frame, 8).empty());
  frame.pixel(40, 50)[2] = std::numeric_limits<float>::quiet_NaN();  // not black: the convolution refuses it
  ASSERT_EQ(lit_regions(frame, 8).size(), 1u);
  EXPECT_EQ(lit_regions(frame, 8)[0], (PixelRect{40, 50, 1, 1}));
  // 25 single lit pixels 20 px apart: 25 boxes, or with at most 16 boxes one bounding box.
  ImageRGBA dots(100, 100, 0.0f);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i) dots.pixel(2 + 20 * i, 3 + 20 * j)[1] = 1.0f;
  EXPECT_EQ(lit_regions(dots, 8, 100).size(), 25u);
  const std::vector<PixelRect> one = lit_regions(dots, 8);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0], (PixelRect{2, 3, 81, 81}));
}

}  // namespace
}  // namespace glarelab
