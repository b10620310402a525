#pragma once
// Text for instruction, break and message screens, rasterised on the CPU with FreeType from
// DejaVu Sans (Debian's fonts-dejavu-core; the path is fixed at configure time, see
// cmake/Dependencies.cmake) into a luminance image that the frame renderer draws like a scene.
// The CPU path keeps text identical on every GL driver: the glyph coverage is FreeType's
// anti-aliased rasterisation, not a driver's texture filtering.
#include <stdexcept>
#include <string>

#include "core/image.h"

namespace glarelab {

class TextError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TextImageStyle {
  double line_height_px = 32;   // distance between baselines; the font's em is line_height / 1.2
  double max_width_px = 0;      // lines wrap at spaces to stay within this width; 0: no wrapping
  double text_cd_m2 = 100;      // luminance of fully covered pixels
  double background_cd_m2 = 0;  // luminance of uncovered pixels
};

// An opaque image (alpha 1) of the text: each pixel is background + coverage * (text - background)
// on all three channels (achromatic, D65 white). '\n' breaks lines; a single word wider than
// max_width_px keeps its line (it is never split). Lines are centred. Invalid UTF-8 bytes show as
// U+FFFD. Empty text gives an empty image. Throws TextError when the font cannot be loaded.
ImageRGBA render_text_image(const std::string& utf8_text, const TextImageStyle& style);

// The font file used (for messages and tests).
std::string text_font_file();

}  // namespace glarelab
