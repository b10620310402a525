#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/png_io.h"
#include "tests/scratch_dir.h"

namespace glarelab {
namespace {

using ::testing::HasSubstr;

// The reference encoding, written out independently of the implementation: clamp to [0, 1],
// then round to the nearest of 256 levels.
int expected_byte(float value) {
  if (std::isnan(value)) return 0;
  const double clamped = std::min(1.0, std::max(0.0, static_cast<double>(value)));
  return static_cast<int>(std::floor(clamped * 255.0 + 0.5));
}

TEST(Png, RoundTripWithinHalfAStep) {
  test::ScratchDir dir;
  const std::string path = dir.file("preview.png");
  ImageRGBA image(31, 17);
  for (int y = 0; y < 17; ++y) {
    for (int x = 0; x < 31; ++x) {
      float* p = image.pixel(x, y);
      p[0] = static_cast<float>(x) / 30.0f;
      p[1] = static_cast<float>(y) / 16.0f;
      p[2] = std::fmod(0.137f * static_cast<float>(x * y), 1.0f);
      p[3] = 0.25f;  // not written: previews are RGB
    }
  }
  write_png_encoded(path, image);
  const ImageRGBA read = read_png_encoded(path);
  ASSERT_EQ(read.width_px, 31);
  ASSERT_EQ(read.height_px, 17);
  for (int y = 0; y < 17; ++y) {
    for (int x = 0; x < 31; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float original = image.pixel(x, y)[c];
        const float decoded = read.pixel(x, y)[c];
        EXPECT_NEAR(decoded, original, 0.5 / 255.0 + 1e-6) << x << "," << y << " channel " << c;
        EXPECT_EQ(decoded, static_cast<float>(expected_byte(original)) / 255.0f);
      }
      EXPECT_EQ(read.pixel(x, y)[3], 1.0f);
    }
  }
}

TEST(Png, OutOfRangeValuesAreClamped) {
  test::ScratchDir dir;
  const std::string path = dir.file("clamped.png");
  ImageRGBA image(4, 1);
  const float values[4][3] = {{-0.5f, 1.7f, std::numeric_limits<float>::quiet_NaN()},
                              {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(), 0.5f},
                              {0.5f / 255.0f, 0.49f / 255.0f, 254.5f / 255.0f},
                              {0.0f, 1.0f, 0.2f}};
  for (int x = 0; x < 4; ++x) {
    for (int c = 0; c < 3; ++c) image.pixel(x, 0)[c] = values[x][c];
  }
  write_png_encoded(path, image);
  const ImageRGBA read = read_png_encoded(path);
  for (int x = 0; x < 4; ++x) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(std::lround(read.pixel(x, 0)[c] * 255.0f), expected_byte(values[x][c])) << x << " channel " << c;
    }
  }
  EXPECT_EQ(read.pixel(0, 0)[0], 0.0f);
  EXPECT_EQ(read.pixel(0, 0)[1], 1.0f);
}

TEST(Png, ReadsAlphaWrittenByLibpng) {
  test::ScratchDir dir;
  const std::string path = dir.file("rgba.png");
  // Written with libpng directly as the reference.
  const std::vector<png_byte> bytes = {255, 0, 0, 255, 0, 128, 0, 64, 0, 0, 255, 0, 10, 20, 30, 200};
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = 2;
  image.height = 2;
  image.format = PNG_FORMAT_RGBA;
  ASSERT_NE(png_image_write_to_file(&image, path.c_str(), 0, bytes.data(), 0, nullptr), 0) << image.message;
  const ImageRGBA read = read_png_encoded(path);
  ASSERT_EQ(read.width_px, 2);
  ASSERT_EQ(read.height_px, 2);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    EXPECT_EQ(read.rgba[i], static_cast<float>(bytes[i]) / 255.0f) << "value " << i;
  }
}

TEST(Png, MissingFileIsAnErrorNamingIt) {
  test::ScratchDir dir;
  const std::string path = dir.file("missing.png");
  try {
    read_png_encoded(path);
    FAIL() << "read a missing file";
  } catch (const ImageError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path));
    EXPECT_THAT(error.what(), HasSubstr("not found"));
  }
}

TEST(Png, NotAPngIsAnErrorNamingIt) {
  test::ScratchDir dir;
  const std::string path = dir.file("text.png");
  test::write_bytes(path, "this is a text file, not a PNG image\n");
  try {
    read_png_encoded(path);
    FAIL() << "read a text file";
  } catch (const ImageError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path + ": "));
  }
  // A truncated PNG fails too.
  const std::string valid = dir.file("valid.png");
  ImageRGBA image(40, 40, 0.3f);
  for (std::size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = static_cast<float>((i * 7919) % 256) / 255.0f;
  write_png_encoded(valid, image);
  const std::string bytes = test::read_bytes(valid);
  const std::string truncated = dir.file("truncated.png");
  test::write_bytes(truncated, bytes.substr(0, bytes.size() / 2));
  try {
    read_png_encoded(truncated);
    FAIL() << "read a truncated PNG";
  } catch (const ImageError& error) {
    EXPECT_THAT(error.what(), HasSubstr(truncated + ": "));
  }
}

TEST(Png, WriteErrorsNameTheFile) {
  test::ScratchDir dir;
  const std::string path = dir.file("no-such-dir/out.png");
  try {
    write_png_encoded(path, ImageRGBA(2, 2, 0.5f));
    FAIL() << "wrote into a missing directory";
  } catch (const ImageError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path + ": "));
  }
  EXPECT_THROW(write_png_encoded(dir.file("empty.png"), ImageRGBA()), ImageError);
}

}  // namespace
}  // namespace glarelab
