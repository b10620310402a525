#include "stimuli/text_image.h"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

namespace glarelab {
namespace {

// Owns the FreeType library and the face. FreeType objects are not thread-safe, so every use of
// the shared face holds font_mutex().
class Font {
 public:
  explicit Font(const std::string& file) {
    if (FT_Init_FreeType(&library_) != 0) throw TextError("FreeType: cannot initialise the library");
    if (FT_New_Face(library_, file.c_str(), 0, &face_) != 0) {
      FT_Done_FreeType(library_);
      throw TextError("FreeType: cannot load the font " + file +
                      " (Debian package fonts-dejavu-core; scripts/setup.sh installs it)");
    }
  }
  ~Font() {
    FT_Done_Face(face_);
    FT_Done_FreeType(library_);
  }
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;
  FT_Face face() const { return face_; }

 private:
  FT_Library library_ = nullptr;
  FT_Face face_ = nullptr;
};

std::mutex& font_mutex() {
  static std::mutex mutex;
  return mutex;
}

Font& shared_font() {
  static Font font(GLARELAB_FONT_FILE);
  return font;
}

// UTF-8 to code points (RFC 3629); an invalid or truncated sequence yields U+FFFD for its first
// byte and decoding goes on at the next byte.
std::vector<char32_t> decode_utf8(const std::string& text) {
  std::vector<char32_t> out;
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char lead = byte(i);
    int length = 0;
    char32_t code = 0;
    if (lead < 0x80) {
      length = 1;
      code = lead;
    } else if ((lead & 0xE0) == 0xC0) {
      length = 2;
      code = lead & 0x1Fu;
    } else if ((lead & 0xF0) == 0xE0) {
      length = 3;
      code = lead & 0x0Fu;
    } else if ((lead & 0xF8) == 0xF0) {
      length = 4;
      code = lead & 0x07u;
    }
    bool valid = length > 0 && i + static_cast<std::size_t>(length) <= text.size();
    for (int k = 1; valid && k < length; ++k) {
      const unsigned char next = byte(i + static_cast<std::size_t>(k));
      if ((next & 0xC0) != 0x80) valid = false;
      code = (code << 6) | (next & 0x3Fu);
    }
    // Overlong forms, surrogates and values past U+10FFFF are invalid too.
    static constexpr char32_t kSmallest[] = {0, 0, 0x80, 0x800, 0x10000};
    if (valid && (code < kSmallest[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF))) valid = false;
    if (!valid) {
      out.push_back(0xFFFD);
      ++i;
      continue;
    }
    out.push_back(code);
    i += static_cast<std::size_t>(length);
  }
  return out;
}

// Horizontal advance of a run of code points in 26.6 fixed point, kerning included.
long advance_26_6(FT_Face face, const std::vector<char32_t>& run) {
  long pen = 0;
  FT_UInt previous = 0;
  for (const char32_t code : run) {
    const FT_UInt glyph = FT_Get_Char_Index(face, code);
    if (previous != 0 && glyph != 0 && FT_HAS_KERNING(face)) {
      FT_Vector kerning{};
      FT_Get_Kerning(face, previous, glyph, FT_KERNING_DEFAULT, &kerning);
      pen += kerning.x;
    }
    if (FT_Load_Glyph(face, glyph, FT_LOAD_DEFAULT) == 0) pen += face->glyph->advance.x;
    previous = glyph;
  }
  return pen;
}

std::vector<std::vector<char32_t>> split_at(const std::vector<char32_t>& text, char32_t separator) {
  std::vector<std::vector<char32_t>> parts(1);
  for (const char32_t code : text) {
    if (code == separator)
      parts.emplace_back();
    else
      parts.back().push_back(code);
  }
  return parts;
}

// Splits into lines: at '\n', and at spaces where a line would grow past max_width (26.6).
std::vector<std::vector<char32_t>> wrap_lines(FT_Face face, const std::vector<char32_t>& text, long max_width_26_6) {
  std::vector<std::vector<char32_t>> lines;
  for (const auto& paragraph : split_at(text, U'\n')) {
    if (max_width_26_6 <= 0) {
      lines.push_back(paragraph);
      continue;
    }
    std::vector<char32_t> line;
    for (const auto& word : split_at(paragraph, U' ')) {
      std::vector<char32_t> candidate = line;
      if (!candidate.empty()) candidate.push_back(U' ');
      candidate.insert(candidate.end(), word.begin(), word.end());
      if (!line.empty() && advance_26_6(face, candidate) > max_width_26_6) {
        lines.push_back(line);
        line = word;
      } else {
        line = std::move(candidate);
      }
    }
    lines.push_back(line);
  }
  return lines;
}

}  // namespace

std::string text_font_file() { return GLARELAB_FONT_FILE; }

ImageRGBA render_text_image(const std::string& utf8_text, const TextImageStyle& style) {
  if (!(style.line_height_px >= 4.0) || !std::isfinite(style.line_height_px))
    throw TextError("text: line height must be at least 4 px, found " + std::to_string(style.line_height_px));
  const std::vector<char32_t> text = decode_utf8(utf8_text);
  if (text.empty()) return {};

  const std::lock_guard<std::mutex> lock(font_mutex());
  FT_Face face = shared_font().face();
  // DejaVu Sans: ascender + descender = 1.164 em, so an em of line_height / 1.2 leaves a small gap.
  const auto em_px = static_cast<FT_UInt>(std::max(1.0, std::round(style.line_height_px / 1.2)));
  if (FT_Set_Pixel_Sizes(face, 0, em_px) != 0)
    throw TextError("FreeType: cannot size the font to " + std::to_string(em_px) + " px");

  const auto line_height = static_cast<int>(std::lround(style.line_height_px));
  const long max_width_26_6 = std::lround(style.max_width_px * 64.0);
  const std::vector<std::vector<char32_t>> lines = wrap_lines(face, text, max_width_26_6);
  std::vector<int> widths;
  int width_px = 1;
  for (const auto& line : lines) {
    widths.push_back(static_cast<int>((advance_26_6(face, line) + 63) / 64));
    width_px = std::max(width_px, widths.back());
  }
  const int height_px = line_height * static_cast<int>(lines.size());
  // Ascender in whole pixels; the line's ink is centred in its line height.
  const auto ascender_px = static_cast<int>(face->size->metrics.ascender / 64);
  const auto descender_px = static_cast<int>(-face->size->metrics.descender / 64);
  const int top_gap_px = std::max(0, (line_height - ascender_px - descender_px) / 2);

  std::vector<float> coverage(static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px), 0.0f);
  for (std::size_t line_index = 0; line_index < lines.size(); ++line_index) {
    const int baseline_y = static_cast<int>(line_index) * line_height + top_gap_px + ascender_px;
    long pen_26_6 = static_cast<long>(width_px - widths[line_index]) * 64 / 2;  // centred
    FT_UInt previous = 0;
    for (const char32_t code : lines[line_index]) {
      const FT_UInt glyph = FT_Get_Char_Index(face, code);
      if (previous != 0 && glyph != 0 && FT_HAS_KERNING(face)) {
        FT_Vector kerning{};
        FT_Get_Kerning(face, previous, glyph, FT_KERNING_DEFAULT, &kerning);
        pen_26_6 += kerning.x;
      }
      previous = glyph;
      if (FT_Load_Glyph(face, glyph, FT_LOAD_RENDER) != 0) continue;
      const FT_GlyphSlot slot = face->glyph;
      const FT_Bitmap& bitmap = slot->bitmap;
      const int origin_x = static_cast<int>(pen_26_6 / 64) + slot->bitmap_left;
      const int origin_y = baseline_y - slot->bitmap_top;
      for (unsigned row = 0; row < bitmap.rows; ++row) {
        const int y = origin_y + static_cast<int>(row);
        if (y < 0 || y >= height_px) continue;
        for (unsigned column = 0; column < bitmap.width; ++column) {
          const int x = origin_x + static_cast<int>(column);
          if (x < 0 || x >= width_px) continue;
          const unsigned char value = bitmap.buffer[static_cast<std::ptrdiff_t>(row) * bitmap.pitch + column];
          float& cell = coverage[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x)];
          cell = std::min(1.0f, cell + static_cast<float>(value) / 255.0f);  // touching glyphs add up
        }
      }
      pen_26_6 += slot->advance.x;
    }
  }

  ImageRGBA image(width_px, height_px);
  const auto background = static_cast<float>(style.background_cd_m2);
  const auto contrast = static_cast<float>(style.text_cd_m2 - style.background_cd_m2);
  for (int y = 0; y < height_px; ++y) {
    for (int x = 0; x < width_px; ++x) {
      const float value =
          background + contrast * coverage[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x)];
      float* pixel = image.pixel(x, y);
      pixel[0] = pixel[1] = pixel[2] = value;
      pixel[3] = 1.0f;
    }
  }
  return image;
}

}  // namespace glarelab
