#include "core/exr_io.h"

#include <Iex.h>
#include <Imath/half.h>
#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFloatAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfRgbaFile.h>
#include <ImfVersion.h>

#include <climits>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <unistd.h>

namespace glarelab {
namespace {

constexpr std::size_t kPixelStride = 4 * sizeof(float);

// Distinguishes the failures a user can act on (wrong path, wrong kind of file) from damage
// inside an OpenEXR file, which only the library can diagnose.
void check_is_exr_file(const std::string& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw ImageError(path + ": file not found");
  if (!std::filesystem::is_regular_file(status)) throw ImageError(path + ": not a regular file");
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw ImageError(path + ": cannot open for reading");
  char magic[4] = {};
  stream.read(magic, sizeof magic);
  if (stream.gcount() != sizeof magic || !Imf::isImfMagic(magic)) throw ImageError(path + ": not an OpenEXR file");
}

std::string channel_names(const Imf::ChannelList& channels) {
  std::string names;
  for (auto it = channels.begin(); it != channels.end(); ++it) {
    if (!names.empty()) names += ",";
    names += it.name();
  }
  return names.empty() ? "no channels" : names;
}

// Luminance/chroma files (Y with RY, BY at reduced resolution) are converted to RGB by the
// library's RGBA interface. It delivers half values, which is what such files store.
void read_luminance_chroma(const std::string& path, ImageRGBA& image, const Imath::Box2i& data_window) {
  Imf::RgbaInputFile file(path.c_str());
  const std::size_t width = static_cast<std::size_t>(image.width_px);
  std::vector<Imf::Rgba> pixels(width * static_cast<std::size_t>(image.height_px));
  // The frame buffer is addressed by absolute pixel coordinates, which start at the data
  // window's corner; the offset is applied as an integer so no out-of-range pointer is formed
  // before the library adds the coordinates back.
  const std::intptr_t origin =
      static_cast<std::intptr_t>(data_window.min.x) + static_cast<std::intptr_t>(data_window.min.y) *
                                                          static_cast<std::intptr_t>(width);
  const auto base = reinterpret_cast<std::uintptr_t>(pixels.data()) -
                    static_cast<std::uintptr_t>(origin) * sizeof(Imf::Rgba);
  file.setFrameBuffer(reinterpret_cast<Imf::Rgba*>(base), 1, width);
  file.readPixels(data_window.min.y, data_window.max.y);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    image.rgba[4 * i + 0] = pixels[i].r;
    image.rgba[4 * i + 1] = pixels[i].g;
    image.rgba[4 * i + 2] = pixels[i].b;
    image.rgba[4 * i + 3] = pixels[i].a;
  }
}

ExrReadResult read_exr_file(const std::string& path) {
  Imf::InputFile file(path.c_str());
  const Imf::Header& header = file.header();
  const Imath::Box2i data_window = header.dataWindow();
  const std::int64_t width = static_cast<std::int64_t>(data_window.max.x) - data_window.min.x + 1;
  const std::int64_t height = static_cast<std::int64_t>(data_window.max.y) - data_window.min.y + 1;
  if (width <= 0 || height <= 0 || width > INT_MAX || height > INT_MAX) {
    throw ImageError(path + ": invalid data window");
  }
  // Checked before any pixel is allocated: a header of a few bytes can declare a data window of
  // billions of pixels (found by the exr fuzz target: 5.2e9 pixels, an 83 GB allocation), and the
  // image is held as float RGBA (16 bytes a pixel) plus a depth channel.
  if (width * height > kMaxExrPixels) {
    throw ImageError(path + ": data window of " + std::to_string(width) + " x " + std::to_string(height) +
                     " px; glarelab reads at most " + std::to_string(kMaxExrPixels) +
                     " pixels (1 GiB as float RGBA, 8 times a 4K display)");
  }

  const Imf::ChannelList& channels = header.channels();
  const Imf::Channel* r = channels.findChannel("R");
  const Imf::Channel* g = channels.findChannel("G");
  const Imf::Channel* b = channels.findChannel("B");
  const Imf::Channel* y = channels.findChannel("Y");
  const Imf::Channel* a = channels.findChannel("A");
  const Imf::Channel* z = channels.findChannel("Z");
  const bool has_rgb = r != nullptr || g != nullptr || b != nullptr;
  if (!has_rgb && y == nullptr) {
    throw ImageError(path + ": no R,G,B or Y channels (has: " + channel_names(channels) + ")");
  }

  ExrReadResult result;
  result.image = ImageRGBA(static_cast<int>(width), static_cast<int>(height));
  result.had_alpha = a != nullptr;
  result.had_depth = z != nullptr;
  ImageRGBA& image = result.image;

  const bool luminance_chroma =
      !has_rgb && (channels.findChannel("RY") != nullptr || channels.findChannel("BY") != nullptr);
  if (luminance_chroma) {
    result.was_half = y->type == Imf::HALF;
    read_luminance_chroma(path, image, data_window);
  } else {
    // Channels read here must be full resolution; only luminance/chroma files subsample.
    for (auto it = channels.begin(); it != channels.end(); ++it) {
      const std::string name = it.name();
      const bool used = name == "R" || name == "G" || name == "B" || name == "A" || name == "Z" ||
                        (name == "Y" && !has_rgb);
      if (used && (it.channel().xSampling != 1 || it.channel().ySampling != 1)) {
        throw ImageError(path + ": channel " + name + " is subsampled, which is not supported");
      }
    }
    result.was_half = true;
    for (const Imf::Channel* colour : {r, g, b}) {
      if (colour != nullptr && colour->type != Imf::HALF) result.was_half = false;
    }
    if (!has_rgb) result.was_half = y->type == Imf::HALF;

    const std::size_t row_stride = kPixelStride * static_cast<std::size_t>(width);
    auto* base = reinterpret_cast<char*>(image.rgba.data());
    // Slice::Make offsets the pointer by the data window corner; channels absent from the file
    // are filled: colour with 0, alpha with 1 (opaque).
    const auto slice = [&](std::size_t component, double fill) {
      return Imf::Slice::Make(Imf::FLOAT, base + component * sizeof(float), data_window, kPixelStride, row_stride, 1,
                              1, fill);
    };
    Imf::FrameBuffer frame_buffer;
    if (has_rgb) {
      frame_buffer.insert("R", slice(0, 0.0));
      frame_buffer.insert("G", slice(1, 0.0));
      frame_buffer.insert("B", slice(2, 0.0));
    } else {
      frame_buffer.insert("Y", slice(0, 0.0));
    }
    frame_buffer.insert("A", slice(3, 1.0));
    if (z != nullptr) {
      result.image.depth.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0.0f);
      frame_buffer.insert("Z", Imf::Slice::Make(Imf::FLOAT, image.depth.data(), data_window, sizeof(float),
                                                sizeof(float) * static_cast<std::size_t>(width)));
    }
    file.setFrameBuffer(frame_buffer);
    file.readPixels(data_window.min.y, data_window.max.y);

    if (!has_rgb) {
      for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
        image.rgba[i + 1] = image.rgba[i];
        image.rgba[i + 2] = image.rgba[i];
      }
    }
  }

  for (auto it = header.begin(); it != header.end(); ++it) {
    if (const auto* attribute = dynamic_cast<const Imf::FloatAttribute*>(&it.attribute())) {
      result.float_attributes[it.name()] = attribute->value();
    }
  }
  return result;
}

}  // namespace

ExrReadResult read_exr(const std::string& path) {
  check_is_exr_file(path);
  try {
    return read_exr_file(path);
  } catch (const ImageError&) {
    throw;
  } catch (const std::exception& error) {
    // Iex exceptions (truncated pixel data, bad headers, unknown compression) derive from
    // std::exception, as do allocation failures for absurd header sizes.
    throw ImageError(path + ": truncated or corrupt: " + error.what());
  }
}

void write_exr(const std::string& path, const ImageRGBA& image, const ExrWriteOptions& options) {
  if (image.empty()) throw ImageError(path + ": cannot write an empty image");
  const std::size_t pixels = static_cast<std::size_t>(image.width_px) * static_cast<std::size_t>(image.height_px);
  if (image.rgba.size() != 4 * pixels) {
    throw ImageError(path + ": image has " + std::to_string(image.rgba.size()) + " values, expected " +
                     std::to_string(4 * pixels));
  }
  if (options.write_depth && image.depth.size() != pixels) {
    throw ImageError(path + ": depth has " + std::to_string(image.depth.size()) + " values, expected " +
                     std::to_string(pixels));
  }

  // Written under a temporary name and renamed, so a failed write never leaves a truncated
  // file under the final name (or destroys the previous one).
  const std::string partial = path + ".partial-" + std::to_string(::getpid());
  try {
    Imf::Header header(image.width_px, image.height_px);
    const Imf::PixelType type = options.pixel_type == ExrPixelType::half ? Imf::HALF : Imf::FLOAT;
    // OutputFile requires slices of the channels' own type: half channels are written from a
    // converted copy (Imath's float to half conversion rounds to nearest even).
    std::vector<half> halves;
    const char* base = reinterpret_cast<const char*>(image.rgba.data());
    std::size_t value_size = sizeof(float);
    if (type == Imf::HALF) {
      halves.assign(image.rgba.begin(), image.rgba.end());
      base = reinterpret_cast<const char*>(halves.data());
      value_size = sizeof(half);
    }
    const std::size_t pixel_stride = 4 * value_size;
    const std::size_t row_stride = pixel_stride * static_cast<std::size_t>(image.width_px);
    Imf::FrameBuffer frame_buffer;
    const auto add = [&](const char* name, std::size_t component) {
      header.channels().insert(name, Imf::Channel(type));
      // The library only reads through this pointer when writing.
      frame_buffer.insert(name, Imf::Slice(type, const_cast<char*>(base) + component * value_size, pixel_stride,
                                           row_stride));
    };
    if (options.luminance_only) {
      add("Y", 0);
    } else {
      add("R", 0);
      add("G", 1);
      add("B", 2);
      if (options.write_alpha) add("A", 3);
    }
    if (options.write_depth) {
      // Depth is always 32-bit float: half has too few bits for distances.
      header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
      frame_buffer.insert("Z", Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(image.depth.data())),
                                          sizeof(float), sizeof(float) * static_cast<std::size_t>(image.width_px)));
    }
    for (const auto& [name, value] : options.float_attributes) header.insert(name, Imf::FloatAttribute(value));

    // ZIP at zlib's fastest level: a float32 frame's low mantissa bits barely compress at any level
    // (a 1024 x 512 glare frame: 4.84 MB at level 1, 4.81 MB at the library's default 4), while
    // level 1 takes 15 to 35 % less time (docs/PERFORMANCE.md, "OpenEXR's zlib level", 2026-12-01).
    if (options.compression == ExrCompression::zip) {
      header.compression() = Imf::ZIP_COMPRESSION;
      header.zipCompressionLevel() = 1;
    } else {
      header.compression() = Imf::NO_COMPRESSION;
    }
    Imf::OutputFile file(partial.c_str(), header);
    file.setFrameBuffer(frame_buffer);
    file.writePixels(image.height_px);
  } catch (const std::exception& error) {
    std::error_code ignored;
    std::filesystem::remove(partial, ignored);
    throw ImageError(path + ": cannot write OpenEXR: " + error.what());
  }
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(partial, ignored);
    throw ImageError(path + ": cannot write OpenEXR: " + error.message());
  }
}

}  // namespace glarelab
