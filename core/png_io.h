#pragma once
// 8-bit PNG previews (display-referred; never for data). libpng.
#include <cstdint>
#include <string>
#include <vector>

#include "core/exr_io.h"

namespace glarelab {

// Writes 8-bit RGB from already display-encoded values in [0, 1] (clamped).
void write_png_encoded(const std::string& path, const ImageRGBA& encoded);
// Reads an 8-bit RGB(A) PNG into values in [0, 1] (no decoding of the transfer function).
ImageRGBA read_png_encoded(const std::string& path);

}  // namespace glarelab
