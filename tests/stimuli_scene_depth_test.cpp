// The scene's depth map: a Z channel read from an EXR file is taken as metres from the eye, +inf as
// a surface at infinity, and every other impossible depth is refused with the file and the first
// bad pixel named; a scene without Z sits at the display's viewing distance.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/exr_io.h"
#include "stimuli/scene_depth.h"
#include "tests/scratch_dir.h"

namespace glarelab {
namespace {

using ::testing::HasSubstr;

ImageRGBA scene_with_depth(int width, int height) {
  ImageRGBA image(width, height, 1.0f);
  image.depth.resize(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.depth[static_cast<std::size_t>(y) * width + x] = static_cast<float>(0.5 + 0.25 * x + 0.125 * y);
  return image;
}

// Writes the scene with its Z channel and reads it back, as the scene library reads scenes.
ExrReadResult through_exr(const ImageRGBA& image, const std::string& path) {
  ExrWriteOptions options;
  options.write_depth = true;
  write_exr(path, image, options);
  return read_exr(path);
}

std::string refusal(const ImageRGBA& image, const std::string& file) {
  try {
    scene_depth_m(image, file, DisplaySpec{});
  } catch (const ImageError& error) {
    return error.what();
  }
  return "(accepted)";
}

TEST(SceneDepthTest, ZChannelFromExrIsTheDepthInMetres) {
  test::ScratchDir scratch;
  const ImageRGBA image = scene_with_depth(6, 4);
  const ExrReadResult read = through_exr(image, (scratch.path() / "scene.exr").string());
  ASSERT_TRUE(read.had_depth);
  const std::vector<float> depth = scene_depth_m(read.image, "scene.exr", DisplaySpec{});
  EXPECT_EQ(depth, image.depth);
  EXPECT_FLOAT_EQ(depth[static_cast<std::size_t>(3 * 6 + 5)], 0.5f + 1.25f + 0.375f);
}

TEST(SceneDepthTest, SceneWithoutZSitsAtTheViewingDistance) {
  ImageRGBA image(5, 3, 2.0f);
  DisplaySpec display;
  display.viewing_distance_mm = 750.0;
  const std::vector<float> depth = scene_depth_m(image, "flat.exr", display);
  ASSERT_EQ(depth.size(), 15u);
  for (float d : depth) EXPECT_FLOAT_EQ(d, 0.75f);
}

TEST(SceneDepthTest, PlusInfinityIsASurfaceAtInfinity) {
  ImageRGBA image = scene_with_depth(4, 4);
  image.depth[5] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(refusal(image, "sky.exr"), "(accepted)");
  EXPECT_EQ(vergence_dioptres(image.depth[5]), 0.0);
  EXPECT_DOUBLE_EQ(vergence_dioptres(0.25), 4.0);
}

TEST(SceneDepthTest, ImpossibleDepthsFromAFileAreRefusedWithTheFirstBadPixelNamed) {
  test::ScratchDir scratch;
  const struct {
    float value;
    const char* word;
  } cases[] = {{std::numeric_limits<float>::quiet_NaN(), "NaN"},
               {-std::numeric_limits<float>::infinity(), "-inf"},
               {0.0f, "zero"},
               {-2.0f, "negative"}};
  for (const auto& bad : cases) {
    ImageRGBA image = scene_with_depth(7, 5);
    image.depth[static_cast<std::size_t>(2 * 7 + 3)] = bad.value;  // pixel (3, 2): the first bad one
    image.depth[static_cast<std::size_t>(4 * 7 + 6)] = bad.value;  // a later one, not named
    const std::string path = (scratch.path() / "bad.exr").string();
    const ExrReadResult read = through_exr(image, path);
    const std::string message = refusal(read.image, path);
    EXPECT_THAT(message, HasSubstr("stimuli/scene_depth: " + path + ": Z at pixel (3, 2) is " + bad.word)) << bad.word;
    EXPECT_THAT(message, HasSubstr("+inf for a surface at infinity"));
    EXPECT_THAT(message, ::testing::Not(HasSubstr("(6, 4)")));
  }
}

TEST(SceneDepthTest, DepthMapOfTheWrongSizeIsRefused) {
  EXPECT_THAT([] { check_scene_depth(std::vector<float>(11, 1.0f), 4, 3, "short.exr"); },
              ::testing::ThrowsMessage<ImageError>(HasSubstr("stimuli/scene_depth: short.exr: the depth map has 11 "
                                                             "values for a 4 x 3 px image")));
}

TEST(SceneDepthTest, ViewingDistanceThatIsNoDistanceIsRefused) {
  DisplaySpec display;
  display.viewing_distance_mm = 0.0;
  EXPECT_THAT([&] { scene_depth_m(ImageRGBA(2, 2, 1.0f), "flat.exr", display); },
              ::testing::ThrowsMessage<ImageError>(HasSubstr("viewing distance")));
}

}  // namespace
}  // namespace glarelab
