#pragma once
// OpenEXR reading and writing (OpenEXR 3): half or float channels, RGB or RGBA, optional Z,
// and Y-only (luminance) images, which read as grey RGB. Errors name the file and what is wrong.
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

#include "core/image.h"

namespace glarelab {

class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class ExrPixelType { half, float32 };

// ZIP (zlib at its fastest level, lossless) or none. A display frame's float32 values barely
// compress (a glare frame's low mantissa bits are noise to zlib: 1024 x 512 RGBA, 8.40 MB raw, 4.39
// to 6.02 MB zipped) at 20 to 27 times the CPU time of writing it as it is (196 to 268 ms against
// 10 ms), so frames a session or `render` writes are stored uncompressed; PSFs and scenes, mostly
// smooth or dark, stay zipped (docs/PERFORMANCE.md, "EXR frames written uncompressed").
enum class ExrCompression { zip, none };

struct ExrWriteOptions {
  ExrPixelType pixel_type = ExrPixelType::float32;
  ExrCompression compression = ExrCompression::zip;
  bool write_alpha = true;
  bool write_depth = false;  // writes "Z" from ImageRGBA::depth (must be filled)
  // Extra float attributes in the header, e.g. {"degreesPerPixel", 0.01}.
  std::map<std::string, float> float_attributes;
  // Single-channel "Y" image (for one-wavelength PSFs) instead of R,G,B[,A]; uses channel R.
  bool luminance_only = false;
};

// How a display frame is written (a session's saved frames, `render`'s EXRs): float32 RGBA,
// uncompressed (ExrCompression says why).
inline ExrWriteOptions display_frame_exr_options() {
  ExrWriteOptions options;
  options.compression = ExrCompression::none;
  return options;
}

struct ExrReadResult {
  ImageRGBA image;
  std::map<std::string, float> float_attributes;
  bool had_alpha = false;
  bool had_depth = false;
  bool was_half = false;
};

// The largest image read_exr takes, in pixels: 2^26, 1 GiB as float RGBA (a stimulus is at most a
// display's size; an 8K display is half of it).
inline constexpr std::int64_t kMaxExrPixels = std::int64_t{1} << 26;

// Throws ImageError "FILE: what is wrong" for missing, unreadable, truncated or corrupt files,
// files without R,G,B or Y channels, and data windows larger than kMaxExrPixels.
ExrReadResult read_exr(const std::string& path);
void write_exr(const std::string& path, const ImageRGBA& image, const ExrWriteOptions& options = {});

}  // namespace glarelab
