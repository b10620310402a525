#include "core/png_io.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <system_error>

namespace glarelab {
namespace {

// [0, 1] to 0..255 with rounding to nearest; NaN (no meaningful value) becomes 0. In double:
// float arithmetic rounds values just below a half-way point (17/30 * 255) up to it.
png_byte encode_8bit(float value) {
  const double clamped = std::isnan(value) ? 0.0 : std::clamp(static_cast<double>(value), 0.0, 1.0);
  return static_cast<png_byte>(clamped * 255.0 + 0.5);
}

}  // namespace

// libpng's simplified API (png_image) does its own error recovery, so no setjmp is needed here;
// failures come back as a zero return and a message in image.message.
void write_png_encoded(const std::string& path, const ImageRGBA& encoded) {
  if (encoded.empty()) throw ImageError(path + ": cannot write an empty image");
  const std::size_t pixels = static_cast<std::size_t>(encoded.width_px) * static_cast<std::size_t>(encoded.height_px);
  if (encoded.rgba.size() != 4 * pixels) {
    throw ImageError(path + ": image has " + std::to_string(encoded.rgba.size()) + " values, expected " +
                     std::to_string(4 * pixels));
  }
  std::vector<png_byte> rgb(3 * pixels);
  for (std::size_t i = 0; i < pixels; ++i) {
    for (std::size_t c = 0; c < 3; ++c) rgb[3 * i + c] = encode_8bit(encoded.rgba[4 * i + c]);
  }

  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(encoded.width_px);
  image.height = static_cast<png_uint_32>(encoded.height_px);
  image.format = PNG_FORMAT_RGB;
  if (png_image_write_to_file(&image, path.c_str(), 0, rgb.data(), 0, nullptr) == 0) {
    const std::string message = image.message;
    png_image_free(&image);
    throw ImageError(path + ": cannot write PNG: " + message);
  }
}

ImageRGBA read_png_encoded(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw ImageError(path + ": file not found");

  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&image, path.c_str()) == 0) {
    // On failure libpng has already released the image's resources.
    throw ImageError(path + ": not a readable PNG: " + image.message);
  }
  // 16-bit files are linear to the simplified API, which would convert them to sRGB when
  // reading 8 bits; these previews are 8-bit only, and values must come back unconverted.
  if ((image.format & PNG_FORMAT_FLAG_LINEAR) != 0) {
    png_image_free(&image);
    throw ImageError(path + ": 16-bit PNG is not supported (8-bit previews only)");
  }
  image.format = PNG_FORMAT_RGBA;
  std::vector<png_byte> bytes(PNG_IMAGE_SIZE(image));
  if (png_image_finish_read(&image, nullptr, bytes.data(), 0, nullptr) == 0) {
    throw ImageError(path + ": truncated or corrupt PNG: " + image.message);
  }

  ImageRGBA result(static_cast<int>(image.width), static_cast<int>(image.height));
  for (std::size_t i = 0; i < bytes.size(); ++i) result.rgba[i] = static_cast<float>(bytes[i]) / 255.0f;
  return result;
}

}  // namespace glarelab
