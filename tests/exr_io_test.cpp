#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Imath/half.h>
#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfRgbaFile.h>
#include <ImfTiledInputFile.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "core/exr_io.h"
#include "tests/scratch_dir.h"

namespace glarelab {
namespace {

using ::testing::HasSubstr;

// Distinct, non-trivial values everywhere (including fractions no binary float short of
// 32 bits holds exactly), so a mixed-up channel or pixel shows.
ImageRGBA test_pattern(int width, int height) {
  ImageRGBA image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      float* p = image.pixel(x, y);
      p[0] = 0.1f * static_cast<float>(x) + 1e-4f * static_cast<float>(y) + 1.0f / 3.0f;
      p[1] = 1000.0f + 0.37f * static_cast<float>(x * y);
      p[2] = std::exp(0.1f * static_cast<float>(x - y));
      p[3] = 1.0f / (1.0f + static_cast<float>(x + y));
    }
  }
  return image;
}

std::string openexr_images_dir() {
  return (std::filesystem::path(GLARELAB_SOURCE_DIR) / ".." / "shared" / "data" / "openexr-images").string();
}

TEST(Exr, FloatRgbaRoundTripIsExact) {
  test::ScratchDir dir;
  const std::string path = dir.file("float.exr");
  const ImageRGBA image = test_pattern(37, 23);
  write_exr(path, image);
  const ExrReadResult read = read_exr(path);
  EXPECT_EQ(read.image.width_px, 37);
  EXPECT_EQ(read.image.height_px, 23);
  EXPECT_TRUE(read.had_alpha);
  EXPECT_FALSE(read.had_depth);
  EXPECT_FALSE(read.was_half);
  EXPECT_TRUE(read.image.depth.empty());
  EXPECT_EQ(read.image.rgba, image.rgba);
  EXPECT_FALSE(std::filesystem::exists(path + ".partial-" + std::to_string(::getpid())));
}

// A frame written uncompressed (what sessions and `render` write) reads back bit for bit, and its
// header says so: ZIP stays the default, and the uncompressed file holds the raw pixels (16 bytes
// a pixel, RGBA float32) with no more than OpenEXR's header and line offsets beside them, where the
// zipped one of a smooth image is smaller.
TEST(Exr, UncompressedFramesRoundTripExactlyAndZipStaysTheDefault) {
  test::ScratchDir dir;
  const ImageRGBA image = test_pattern(64, 48);
  const std::string zipped = dir.file("zipped.exr"), raw = dir.file("raw.exr");
  write_exr(zipped, image);
  ExrWriteOptions uncompressed;
  uncompressed.compression = ExrCompression::none;
  write_exr(raw, image, uncompressed);
  EXPECT_EQ(read_exr(raw).image.rgba, image.rgba);
  EXPECT_EQ(read_exr(zipped).image.rgba, image.rgba);
  EXPECT_EQ(Imf::InputFile(raw.c_str()).header().compression(), Imf::NO_COMPRESSION);
  EXPECT_EQ(Imf::InputFile(zipped.c_str()).header().compression(), Imf::ZIP_COMPRESSION);
  const std::uintmax_t pixel_bytes = 64u * 48u * 16u;
  EXPECT_GE(std::filesystem::file_size(raw), pixel_bytes);
  EXPECT_LT(std::filesystem::file_size(raw), pixel_bytes + 2048u);
  EXPECT_LT(std::filesystem::file_size(zipped), std::filesystem::file_size(raw));
}

TEST(Exr, RgbWithoutAlphaReadsOpaque) {
  test::ScratchDir dir;
  const std::string path = dir.file("rgb.exr");
  const ImageRGBA image = test_pattern(8, 5);
  ExrWriteOptions options;
  options.write_alpha = false;
  write_exr(path, image, options);
  const ExrReadResult read = read_exr(path);
  EXPECT_FALSE(read.had_alpha);
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
    EXPECT_EQ(read.image.rgba[i + 0], image.rgba[i + 0]);
    EXPECT_EQ(read.image.rgba[i + 1], image.rgba[i + 1]);
    EXPECT_EQ(read.image.rgba[i + 2], image.rgba[i + 2]);
    EXPECT_EQ(read.image.rgba[i + 3], 1.0f);
  }
}

TEST(Exr, HalfRoundTripIsWithinHalfPrecision) {
  test::ScratchDir dir;
  const std::string path = dir.file("half.exr");
  // Values across the normal half range, 6.1e-5 to 65504, most of them not representable.
  ImageRGBA image(64, 4);
  for (std::size_t i = 0; i < image.rgba.size(); ++i) {
    image.rgba[i] = 1e-3f * std::pow(1.37f, static_cast<float>(i % 50)) * (1.0f + 0.001f * static_cast<float>(i));
  }
  ExrWriteOptions options;
  options.pixel_type = ExrPixelType::half;
  write_exr(path, image, options);
  const ExrReadResult read = read_exr(path);
  EXPECT_TRUE(read.was_half);
  ASSERT_EQ(read.image.rgba.size(), image.rgba.size());
  for (std::size_t i = 0; i < image.rgba.size(); ++i) {
    // Half has an 11-bit significand: rounding error at most 2^-11 = 4.9e-4 relative.
    EXPECT_NEAR(read.image.rgba[i], image.rgba[i], 1e-3 * image.rgba[i]) << "value " << i;
  }
}

TEST(Exr, HalfRoundTripIsExactForHalfValues) {
  test::ScratchDir dir;
  const std::string path = dir.file("half-exact.exr");
  // Representable in half: k/1024 (11 significant bits or fewer), powers of two, 65504 (max),
  // 2^-24 (smallest subnormal), zero and negative values.
  const float values[] = {0.0f, -0.0f, 1.0f, 0.5f, 0.25f, 2.0f, 1024.0f, 65504.0f, 0x1.0p-24f, 0x1.0p-14f,
                          -3.5f, 0.0009765625f, 1.5f, 1023.0f / 1024.0f, 2047.0f, 100.0f};
  ImageRGBA image(4, 4);
  for (std::size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = values[i % std::size(values)];
  ExrWriteOptions options;
  options.pixel_type = ExrPixelType::half;
  write_exr(path, image, options);
  const ExrReadResult read = read_exr(path);
  for (std::size_t i = 0; i < image.rgba.size(); ++i) {
    ASSERT_EQ(static_cast<float>(half(image.rgba[i])), image.rgba[i]) << "test value not a half";
    EXPECT_EQ(read.image.rgba[i], image.rgba[i]) << "value " << i;
  }
}

TEST(Exr, DepthChannelRoundTrip) {
  test::ScratchDir dir;
  const std::string path = dir.file("depth.exr");
  ImageRGBA image = test_pattern(9, 7);
  image.depth.resize(9 * 7);
  for (std::size_t i = 0; i < image.depth.size(); ++i) image.depth[i] = 0.3f + 17.123f * static_cast<float>(i);
  ExrWriteOptions options;
  options.write_depth = true;
  options.pixel_type = ExrPixelType::half;  // depth stays 32-bit float regardless
  write_exr(path, image, options);
  const ExrReadResult read = read_exr(path);
  EXPECT_TRUE(read.had_depth);
  EXPECT_EQ(read.image.depth, image.depth);

  // Asking for depth without supplying it is an error, not garbage in the file.
  ImageRGBA no_depth = test_pattern(3, 3);
  EXPECT_THROW(write_exr(dir.file("bad.exr"), no_depth, options), ImageError);
}

TEST(Exr, LuminanceOnlyWritesYAndReadsGrey) {
  test::ScratchDir dir;
  const std::string path = dir.file("psf.exr");
  const ImageRGBA image = test_pattern(11, 6);
  ExrWriteOptions options;
  options.luminance_only = true;
  write_exr(path, image, options);

  // The file has exactly one channel, "Y".
  Imf::RgbaInputFile check(path.c_str());
  const Imf::ChannelList& channels = check.header().channels();
  std::vector<std::string> names;
  for (auto it = channels.begin(); it != channels.end(); ++it) names.emplace_back(it.name());
  EXPECT_EQ(names, std::vector<std::string>{"Y"});

  const ExrReadResult read = read_exr(path);
  EXPECT_FALSE(read.had_alpha);
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 11; ++x) {
      const float expected = image.pixel(x, y)[0];
      const float* p = read.image.pixel(x, y);
      EXPECT_EQ(p[0], expected);
      EXPECT_EQ(p[1], expected);
      EXPECT_EQ(p[2], expected);
      EXPECT_EQ(p[3], 1.0f);
    }
  }
}

TEST(Exr, FloatAttributeRoundTrip) {
  test::ScratchDir dir;
  const std::string path = dir.file("attributes.exr");
  ExrWriteOptions options;
  options.float_attributes = {{"degreesPerPixel", 0.0123f}, {"peakLuminance", 25000.5f}};
  write_exr(path, test_pattern(4, 4), options);
  const ExrReadResult read = read_exr(path);
  ASSERT_EQ(read.float_attributes.count("degreesPerPixel"), 1u);
  EXPECT_EQ(read.float_attributes.at("degreesPerPixel"), 0.0123f);
  EXPECT_EQ(read.float_attributes.at("peakLuminance"), 25000.5f);
  // Standard float attributes come along too.
  EXPECT_EQ(read.float_attributes.at("pixelAspectRatio"), 1.0f);
}

TEST(Exr, DataWindowOffsetIsHandled) {
  test::ScratchDir dir;
  const std::string path = dir.file("offset.exr");
  const int width = 13;
  const int height = 7;
  const auto value = [](int x, int y, int channel) {
    return static_cast<float>(1000 * channel + 10 * x) + 0.01f * static_cast<float>(y);
  };
  {
    // Written with the library directly: display window 0..99, data window (10,20)-(22,26),
    // values a function of the absolute pixel coordinates.
    const Imath::Box2i display_window(Imath::V2i(0, 0), Imath::V2i(99, 99));
    const Imath::Box2i data_window(Imath::V2i(10, 20), Imath::V2i(10 + width - 1, 20 + height - 1));
    Imf::Header header(display_window, data_window);
    std::vector<float> planes[3];
    const char* names[3] = {"R", "G", "B"};
    Imf::FrameBuffer frame_buffer;
    for (int c = 0; c < 3; ++c) {
      header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
      planes[c].resize(static_cast<std::size_t>(width * height));
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) planes[c][static_cast<std::size_t>(y * width + x)] = value(10 + x, 20 + y, c);
      }
      frame_buffer.insert(names[c], Imf::Slice::Make(Imf::FLOAT, planes[c].data(), data_window));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame_buffer);
    file.writePixels(height);
  }
  const ExrReadResult read = read_exr(path);
  ASSERT_EQ(read.image.width_px, width);
  ASSERT_EQ(read.image.height_px, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(read.image.pixel(x, y)[c], value(10 + x, 20 + y, c)) << x << "," << y << " channel " << c;
      }
      EXPECT_EQ(read.image.pixel(x, y)[3], 1.0f);
    }
  }
}

TEST(Exr, NoColourChannelsIsAnError) {
  test::ScratchDir dir;
  const std::string path = dir.file("mask.exr");
  {
    Imf::Header header(2, 2);
    header.channels().insert("mask", Imf::Channel(Imf::FLOAT));
    std::vector<float> mask(4, 1.0f);
    Imf::FrameBuffer frame_buffer;
    frame_buffer.insert("mask", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(mask.data()), sizeof(float),
                                           2 * sizeof(float)));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame_buffer);
    file.writePixels(2);
  }
  try {
    read_exr(path);
    FAIL() << "read an image without colour";
  } catch (const ImageError& error) {
    EXPECT_EQ(std::string(error.what()), path + ": no R,G,B or Y channels (has: mask)");
  }
}

// A 312-byte file whose header declares a data window of 5.2e9 pixels (found by the exr fuzz
// target: the reader allocated 83 GB for it before reading a pixel) is refused from its header.
TEST(Exr, ADataWindowLargerThanAnyStimulusIsRefusedBeforeAllocating) {
  const std::string path = std::string(GLARELAB_SOURCE_DIR) + "/fuzz/corpus/exr/huge_data_window.exr";
  try {
    read_exr(path);
    FAIL() << "read a header declaring billions of pixels";
  } catch (const ImageError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path + ": data window of "));
    EXPECT_THAT(error.what(), HasSubstr(" px; glarelab reads at most 67108864 pixels"));
  }
  // An image wider than a GL texture still reads: the bound is on pixels; a stimulus's size is
  // checked by the scene library.
  test::ScratchDir dir;
  const std::string wide = dir.file("wide.exr");
  write_exr(wide, ImageRGBA(16385, 2));
  EXPECT_EQ(read_exr(wide).image.width_px, 16385);
}

TEST(Exr, MissingFileIsNotFound) {
  test::ScratchDir dir;
  const std::string path = dir.file("does-not-exist.exr");
  try {
    read_exr(path);
    FAIL() << "read a missing file";
  } catch (const ImageError& error) {
    EXPECT_THAT(error.what(), HasSubstr("not found"));
    EXPECT_THAT(error.what(), HasSubstr(path));
  }
}

TEST(Exr, RandomBytesAreNotAnExrFile) {
  test::ScratchDir dir;
  const std::string path = dir.file("noise.exr");
  std::mt19937 generator(5);
  std::string bytes(4096, '\0');
  for (char& byte : bytes) byte = static_cast<char>(generator() & 0xff);
  test::write_bytes(path, bytes);
  try {
    read_exr(path);
    FAIL() << "read random bytes";
  } catch (const ImageError& error) {
    EXPECT_EQ(std::string(error.what()), path + ": not an OpenEXR file");
  }
}

TEST(Exr, CorruptFilesNameTheFile) {
  test::ScratchDir dir;
  const std::string valid = dir.file("valid.exr");
  ImageRGBA image(64, 64);
  std::mt19937 generator(9);
  std::uniform_real_distribution<float> noise(0.0f, 100.0f);  // incompressible pixel data
  for (float& value : image.rgba) value = noise(generator);
  write_exr(valid, image);
  const std::string bytes = test::read_bytes(valid);

  const std::string truncated = dir.file("truncated.exr");
  test::write_bytes(truncated, bytes.substr(0, bytes.size() / 2));
  try {
    read_exr(truncated);
    FAIL() << "read a truncated file";
  } catch (const ImageError& error) {
    EXPECT_THAT(error.what(), HasSubstr(truncated + ": truncated or corrupt: "));
  }

  // The header intact, the rest overwritten: the offset table points nowhere.
  std::string scrambled = bytes;
  for (std::size_t i = scrambled.size() / 8; i < scrambled.size(); ++i) {
    scrambled[i] = static_cast<char>(generator() & 0xff);
  }
  const std::string corrupt = dir.file("scrambled.exr");
  test::write_bytes(corrupt, scrambled);
  try {
    read_exr(corrupt);
    FAIL() << "read a scrambled file";
  } catch (const ImageError& error) {
    EXPECT_THAT(error.what(), HasSubstr(corrupt + ": "));
  }

  const std::string empty = dir.file("empty.exr");
  test::write_bytes(empty, "");
  EXPECT_THROW(read_exr(empty), ImageError);
}

TEST(Exr, WriteErrorsNameTheFile) {
  test::ScratchDir dir;
  const std::string path = dir.file("no-such-dir/out.exr");
  try {
    write_exr(path, test_pattern(2, 2));
    FAIL() << "wrote into a missing directory";
  } catch (const ImageError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path + ": "));
  }
  EXPECT_THROW(write_exr(dir.file("empty.exr"), ImageRGBA()), ImageError);
}

// Reference images from the OpenEXR project, read from the shared data directory when present.
class ExrSampleImages : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = openexr_images_dir();
    if (!std::filesystem::is_directory(directory_)) {
      GTEST_SKIP() << "OpenEXR sample images not available at " << directory_;
    }
  }
  std::string file(const std::string& name) const { return directory_ + "/" + name; }
  std::string directory_;
};

TEST_F(ExrSampleImages, CandleGlassHasNegativePixels) {
  const std::string path = file("ScanLines_CandleGlass.exr");
  const ExrReadResult read = read_exr(path);
  EXPECT_EQ(read.image.width_px, 1000);
  EXPECT_EQ(read.image.height_px, 810);
  const NonFiniteReport report = inspect_pixels(read.image);
  EXPECT_GT(report.negative_pixels, 0u) << report.describe();

  // Independent reference: the library's RGBA interface, which converts everything to half.
  Imf::RgbaInputFile reference(path.c_str());
  const Imath::Box2i window = reference.dataWindow();
  const int width = window.max.x - window.min.x + 1;
  const int height = window.max.y - window.min.y + 1;
  ASSERT_EQ(width, 1000);
  ASSERT_EQ(height, 810);
  std::vector<Imf::Rgba> pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  reference.setFrameBuffer(pixels.data() - window.min.x - window.min.y * width, 1, static_cast<std::size_t>(width));
  reference.readPixels(window.min.y, window.max.y);
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const float* p = &read.image.rgba[4 * i];
    if (read.was_half) {
      mismatches += (static_cast<float>(pixels[i].r) != p[0] || static_cast<float>(pixels[i].g) != p[1] ||
                     static_cast<float>(pixels[i].b) != p[2])
                        ? 1
                        : 0;
    } else {
      mismatches += (std::abs(static_cast<float>(pixels[i].r) - p[0]) > 1e-3f * std::abs(p[0]) + 1e-6f) ? 1 : 0;
    }
  }
  EXPECT_EQ(mismatches, 0u);
}

TEST_F(ExrSampleImages, BrightRingsNanInfHasNaNAndInf) {
  const ExrReadResult read = read_exr(file("TestImages_BrightRingsNanInf.exr"));
  const NonFiniteReport report = inspect_pixels(read.image);
  EXPECT_GT(report.nan_pixels, 0u) << report.describe();
  EXPECT_GT(report.inf_pixels, 0u) << report.describe();
  // The same image without the planted values is clean of NaN and Inf.
  const ExrReadResult clean = read_exr(file("TestImages_BrightRings.exr"));
  EXPECT_EQ(inspect_pixels(clean.image).nan_pixels, 0u);
  EXPECT_EQ(inspect_pixels(clean.image).inf_pixels, 0u);
}

TEST_F(ExrSampleImages, MipMappedFileReadsBaseLevel) {
  const std::string path = file("MultiResolution_StageEnvLatLong.exr");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not available";
  Imf::TiledInputFile reference(path.c_str());
  const ExrReadResult read = read_exr(path);
  EXPECT_EQ(read.image.width_px, reference.levelWidth(0));
  EXPECT_EQ(read.image.height_px, reference.levelHeight(0));
  EXPECT_GT(max_luminance(read.image), 0.0);
}

}  // namespace
}  // namespace glarelab
