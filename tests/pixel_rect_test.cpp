// core/pixel_rect.h against rectangles and images worked by hand: the half-open convention (a
// rectangle that only touches another along an edge shares no pixel with it), the bounding box
// leaving empty rectangles out wherever their corner lies, and crop and paste clipped at an
// image's edge, depth included.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "core/pixel_rect.h"

namespace glarelab {
namespace {

// A 5 x 4 image whose channel c at (x, y) holds 100 y + 10 x + c, and depth 1000 + 10 y + x.
ImageRGBA numbered_image() {
  ImageRGBA image(5, 4);
  image.depth.resize(20);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) {
      for (int c = 0; c < 4; ++c) image.pixel(x, y)[c] = static_cast<float>(100 * y + 10 * x + c);
      image.depth[static_cast<std::size_t>(5 * y + x)] = static_cast<float>(1000 + 10 * y + x);
    }
  return image;
}

TEST(PixelRect, EdgesAreHalfOpen) {
  const PixelRect a{10, 20, 30, 40};  // columns 10..39, rows 20..59
  EXPECT_EQ(a.right_px(), 40);
  EXPECT_EQ(a.bottom_px(), 60);
  EXPECT_FALSE(a.empty());
  EXPECT_TRUE((PixelRect{5, 5, 0, 3}).empty());
  EXPECT_TRUE((PixelRect{5, 5, 3, -1}).empty());
  EXPECT_TRUE(a.contains(a));
  EXPECT_TRUE(a.contains(PixelRect{39, 59, 1, 1}));   // the last pixel
  EXPECT_FALSE(a.contains(PixelRect{39, 59, 2, 1}));  // one column past it
  EXPECT_FALSE(a.contains(PixelRect{9, 20, 1, 1}));
  EXPECT_EQ(image_rect(ImageRGBA(7, 3)), (PixelRect{0, 0, 7, 3}));
}

TEST(PixelRect, IntersectionOverlappingTouchingDisjointAndClipped) {
  const PixelRect a{10, 20, 30, 40};
  EXPECT_EQ(intersection(a, PixelRect{30, 50, 100, 100}), (PixelRect{30, 50, 10, 10}));
  EXPECT_EQ(intersection(PixelRect{30, 50, 100, 100}, a), (PixelRect{30, 50, 10, 10}));
  EXPECT_EQ(intersection(a, PixelRect{12, 22, 3, 4}), (PixelRect{12, 22, 3, 4}));
  // Touching along x = 40 and along y = 60: nothing shared, 0 x 0 at the first one's corner.
  EXPECT_EQ(intersection(a, PixelRect{40, 20, 5, 5}), (PixelRect{10, 20, 0, 0}));
  EXPECT_EQ(intersection(a, PixelRect{10, 60, 5, 5}), (PixelRect{10, 20, 0, 0}));
  EXPECT_TRUE(intersection(a, PixelRect{100, 100, 5, 5}).empty());
  // Clipped at a 32 x 24 image's edges, on both sides.
  EXPECT_EQ(intersection(PixelRect{-3, 20, 10, 10}, PixelRect{0, 0, 32, 24}), (PixelRect{0, 20, 7, 4}));
  EXPECT_EQ(intersection(PixelRect{28, -2, 10, 5}, PixelRect{0, 0, 32, 24}), (PixelRect{28, 0, 4, 3}));
  EXPECT_TRUE(intersection(PixelRect{32, 0, 4, 4}, PixelRect{0, 0, 32, 24}).empty());
}

TEST(PixelRect, BoundingRectOfTwoAndOfAList) {
  EXPECT_EQ(bounding_rect(PixelRect{10, 10, 40, 30}, PixelRect{70, 20, 40, 50}), (PixelRect{10, 10, 100, 60}));
  // Touching: the two together, exactly.
  EXPECT_EQ(bounding_rect(PixelRect{0, 0, 4, 2}, PixelRect{4, 0, 4, 2}), (PixelRect{0, 0, 8, 2}));
  // One inside the other.
  EXPECT_EQ(bounding_rect(PixelRect{0, 0, 10, 10}, PixelRect{2, 3, 1, 1}), (PixelRect{0, 0, 10, 10}));
  // An empty one holds no pixel, however far away its corner.
  EXPECT_EQ(bounding_rect(PixelRect{500, 500, 0, 9}, PixelRect{3, 4, 5, 6}), (PixelRect{3, 4, 5, 6}));
  EXPECT_EQ(bounding_rect(PixelRect{3, 4, 5, 6}, PixelRect{-50, -50, 9, 0}), (PixelRect{3, 4, 5, 6}));
  EXPECT_EQ(bounding_rect(PixelRect{7, 7, 0, 0}, PixelRect{9, 9, 0, 3}), (PixelRect{0, 0, 0, 0}));
  const std::vector<PixelRect> three = {{40, 50, 1, 1}, {2, 3, 10, 10}, {60, 1, 23, 5}, {-9, -9, 0, 0}};
  EXPECT_EQ(bounding_rect(three), (PixelRect{2, 1, 81, 50}));
  EXPECT_EQ(bounding_rect(std::vector<PixelRect>{}), (PixelRect{0, 0, 0, 0}));
}

TEST(PixelRect, CropInsideAndClippedAtTheEdge) {
  const ImageRGBA image = numbered_image();
  const ImageRGBA inner = crop(image, PixelRect{1, 2, 3, 2});
  ASSERT_EQ(inner.width_px, 3);
  ASSERT_EQ(inner.height_px, 2);
  EXPECT_EQ(inner.pixel(0, 0)[0], 210.0f);  // (1, 2)
  EXPECT_EQ(inner.pixel(2, 1)[3], 333.0f);  // (3, 3), alpha
  ASSERT_EQ(inner.depth.size(), 6u);
  EXPECT_EQ(inner.depth, (std::vector<float>{1021, 1022, 1023, 1031, 1032, 1033}));
  // Reaching past the right and bottom edges: the 2 x 2 pixels from (3, 2).
  const ImageRGBA corner = crop(image, PixelRect{3, 2, 5, 5});
  ASSERT_EQ(corner.width_px, 2);
  ASSERT_EQ(corner.height_px, 2);
  EXPECT_EQ(corner.pixel(0, 0)[1], 231.0f);
  EXPECT_EQ(corner.pixel(1, 1)[2], 342.0f);
  EXPECT_EQ(corner.depth, (std::vector<float>{1023, 1024, 1033, 1034}));
  // Reaching past the left and top edges.
  const ImageRGBA top_left = crop(image, PixelRect{-2, -1, 3, 2});
  ASSERT_EQ(top_left.width_px, 1);
  ASSERT_EQ(top_left.height_px, 1);
  EXPECT_EQ(top_left.pixel(0, 0)[0], 0.0f);
  // Outside, or only touching: an empty image.
  EXPECT_TRUE(crop(image, PixelRect{5, 0, 2, 2}).empty());
  EXPECT_TRUE(crop(image, PixelRect{1, 1, 0, 2}).empty());
  // Without depth, none comes back.
  ImageRGBA flat = image;
  flat.depth.clear();
  EXPECT_TRUE(crop(flat, PixelRect{0, 0, 2, 2}).depth.empty());
}

TEST(PixelRect, PasteInsideAndClippedAtTheEdge) {
  const ImageRGBA image = numbered_image();
  ImageRGBA into(5, 4, -1.0f);
  into.depth.assign(20, -1.0f);
  // A 2 x 2 patch at (4, 3): only its top-left pixel lands inside.
  paste(into, crop(image, PixelRect{0, 0, 2, 2}), PixelRect{4, 3, 2, 2});
  EXPECT_EQ(into.pixel(4, 3)[0], 0.0f);
  EXPECT_EQ(into.pixel(4, 3)[3], 3.0f);
  EXPECT_EQ(into.depth[19], 1000.0f);
  EXPECT_EQ(into.pixel(3, 3)[0], -1.0f);
  EXPECT_EQ(into.pixel(4, 2)[0], -1.0f);
  // At (-1, -1): only the patch's bottom-right pixel lands, at (0, 0).
  paste(into, crop(image, PixelRect{2, 1, 2, 2}), PixelRect{-1, -1, 2, 2});
  EXPECT_EQ(into.pixel(0, 0)[2], 232.0f);  // the patch's (1, 1) is the image's (3, 2)
  EXPECT_EQ(into.depth[0], 1023.0f);
  EXPECT_EQ(into.pixel(1, 0)[0], -1.0f);
  // Crop then paste at the same place is the identity on that rectangle.
  paste(into, crop(image, PixelRect{1, 1, 3, 2}), PixelRect{1, 1, 3, 2});
  for (int y = 1; y < 3; ++y)
    for (int x = 1; x < 4; ++x)
      for (int c = 0; c < 4; ++c) EXPECT_EQ(into.pixel(x, y)[c], image.pixel(x, y)[c]) << x << " " << y << " " << c;
  // A patch without depth leaves the depth as it was.
  ImageRGBA flat(1, 1, 7.0f);
  paste(into, flat, PixelRect{2, 0, 1, 1});
  EXPECT_EQ(into.pixel(2, 0)[0], 7.0f);
  EXPECT_EQ(into.depth[2], -1.0f);
  // Wholly outside: nothing written; a rectangle not the patch's size: refused.
  const ImageRGBA before = into;
  paste(into, flat, PixelRect{5, 0, 1, 1});
  EXPECT_EQ(into.rgba, before.rgba);
  EXPECT_THROW(paste(into, flat, PixelRect{0, 0, 2, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab
