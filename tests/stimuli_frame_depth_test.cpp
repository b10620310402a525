// A composed frame's depth map (stimuli/frame_depth.h): placed scenes' Z where they are drawn, the
// display's distance elsewhere, worked by hand; and its warp through a lens, which moves the depths
// with the frame's own warp (stimuli/spectacle_warp.h) and never invents a depth between two.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "glare/refraction/spectacle_lens.h"
#include "stimuli/frame_depth.h"
#include "stimuli/spectacle_warp.h"

namespace glarelab {
namespace {

TEST(FrameDepthTest, PlacedScenesGiveTheirDepthWhereTheyAreDrawn) {
  ImageRGBA with_z(4, 3, 1.0f);
  with_z.depth = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  const ImageRGBA without_z(2, 2, 1.0f);
  // The first scene at (3, 1), its column clipped at x < 5; the second at (0, 0).
  const std::vector<float> depth =
      composed_depth_m(8, 5, 0.5f, {{&with_z, {3, 1, 4, 3}, {0, 0, 5, 5}}, {&without_z, {0, 0, 2, 2}, {0, 0, 8, 5}}});
  const auto at = [&](int x, int y) { return depth[static_cast<std::size_t>(y) * 8 + x]; };
  EXPECT_EQ(at(3, 1), 1.0f);
  EXPECT_EQ(at(4, 1), 2.0f);
  EXPECT_EQ(at(5, 1), 0.5f);  // clipped
  EXPECT_EQ(at(4, 3), 10.0f);
  EXPECT_EQ(at(0, 0), 0.5f);  // a scene without Z lies at the display's distance
  EXPECT_EQ(at(7, 4), 0.5f);
}

// A near square on a far wall through a +4 D lens: where the frame's warp of a flat colour-coded
// copy (bilinear) is one region's value, the warped depth is that region's depth; and every warped
// depth is one of the two, none in between.
TEST(FrameDepthTest, DepthMovesWithTheFrameThroughTheLens) {
  const int width = 121, height = 81;
  const SpectacleFrame frame{width, height, 0.05};
  SpectacleLensSpec spec;
  spec.prescription.sphere_dioptres = 4.0;
  const SpectacleLens lens(spec);
  std::vector<float> depth(static_cast<std::size_t>(width) * height, 2.0f);
  ImageRGBA coded(width, height, 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const bool near = x >= 70 && x < 100 && y >= 20 && y < 50;
      if (near) depth[static_cast<std::size_t>(y) * width + x] = 0.4f;
      for (int c = 0; c < 3; ++c) coded.pixel(x, y)[c] = near ? 1.0f : 0.0f;
    }
  const std::vector<float> seen = depth_through_spectacles(depth, lens, frame, 400.0, 2.0f, 2);
  SpectacleWarpOptions options;
  options.scene_distance_mm = 400.0;
  const ImageRGBA warped = warp_through_spectacles(coded, lens, frame, options);
  int moved = 0;
  std::set<float> values;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float d = seen[static_cast<std::size_t>(y) * width + x];
      values.insert(d);
      const float g = warped.pixel(x, y)[1];
      if (g == 1.0f) {
        EXPECT_EQ(d, 0.4f) << x << ", " << y;
      }
      if (g == 0.0f) {
        EXPECT_EQ(d, 2.0f) << x << ", " << y;
      }
      if (d != depth[static_cast<std::size_t>(y) * width + x]) ++moved;
    }
  EXPECT_EQ(values, (std::set<float>{0.4f, 2.0f}));
  EXPECT_GT(moved, 100);  // the lens magnifies: the square's edges move by pixels
}

}  // namespace
}  // namespace glarelab
