// Writes the near target of examples/presbyope_reading_glasses.toml (examples/scenes/reading_desk.exr):
// a page of text 0.4 m from the eye over the display centre, a desk lamp's bulb behind it at 1 m
// and a wall at 3 m, with a Z channel (metres from the eye) for the depth of field
// (docs/DEPTH_OF_FIELD.md, "In a session"). Run by `make reading_scene` (scripts/CMakeLists.txt);
// the result is committed so the example needs nothing but a clone.
//   usage: make_reading_scene OUTPUT_DIR
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/exr_io.h"
#include "stimuli/text_image.h"

namespace {

// The example's display: 512 x 384 px of 0.25 mm at 0.4 m (0.0358 degrees a pixel).
constexpr int kWidth = 512, kHeight = 384;
constexpr float kPageM = 0.4f, kLampM = 1.0f, kWallM = 3.0f;
// Luminances (cd/m2) for the example's 250 cd/m2 display: a dim wall, a lit page, ink, the lamp's
// shade and its bulb (0.1 degrees, 90 % of the peak, as the generated desk lamp had).
constexpr float kWall = 3.0f, kPaper = 40.0f, kInk = 2.0f, kShade = 12.0f, kBulb = 225.0f;

void fill(glarelab::ImageRGBA& image, int x, int y, float luminance, float depth_m) {
  float* p = image.pixel(x, y);
  p[0] = p[1] = p[2] = luminance;
  p[3] = 1.0f;
  image.depth[static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x)] = depth_m;
}

glarelab::ImageRGBA reading_desk() {
  glarelab::ImageRGBA image(kWidth, kHeight);
  image.depth.assign(static_cast<std::size_t>(kWidth) * kHeight, kWallM);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) fill(image, x, y, kWall * (1.0f - 0.3f * static_cast<float>(y) / kHeight), kWallM);
  // The lamp above the page: a shade (a 40 x 16 px band) and the bulb below it, a disc of
  // 0.1 degrees (2.8 px) with its edge antialiased from 4 x 4 subsamples.
  const double bulb_x = 256.0, bulb_y = 74.0, bulb_radius_px = 1.4;
  for (int y = 50; y < 84; ++y)
    for (int x = 226; x < 286; ++x) {
      int covered = 0;
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx) {
          const double dx = x + (sx + 0.5) / 4.0 - 0.5 - bulb_x, dy = y + (sy + 0.5) / 4.0 - 0.5 - bulb_y;
          covered += dx * dx + dy * dy <= bulb_radius_px * bulb_radius_px ? 1 : 0;
        }
      const bool shade = y < 70 && std::abs(x - 256) < 20 + (y - 50);
      if (covered > 0) {
        const float coverage = static_cast<float>(covered) / 16.0f;
        fill(image, x, y, coverage * kBulb + (1.0f - coverage) * (shade ? kShade : kWall), kLampM);
      } else if (shade) {
        fill(image, x, y, kShade, kLampM);
      }
    }
  // The page: 300 x 200 px (7.5 x 5 cm at 0.4 m) centred on the display, lines of text from 24 px
  // down to 8 px (0.86 to 0.29 degrees between baselines), as a reading chart.
  const int page_x = 106, page_y = 112, page_w = 300, page_h = 200;
  for (int y = page_y; y < page_y + page_h; ++y)
    for (int x = page_x; x < page_x + page_w; ++x) fill(image, x, y, kPaper, kPageM);
  int line_y = page_y + 8;
  for (const double line_px : {24.0, 18.0, 14.0, 11.0, 9.0, 8.0}) {
    glarelab::TextImageStyle style;
    style.line_height_px = line_px;
    style.text_cd_m2 = kInk;
    style.background_cd_m2 = kPaper;
    const glarelab::ImageRGBA text = glarelab::render_text_image("the near zone of a reading lens", style);
    const int x0 = page_x + (page_w - text.width_px) / 2;
    for (int y = 0; y < text.height_px && line_y + y < page_y + page_h; ++y)
      for (int x = 0; x < text.width_px; ++x)
        if (x0 + x >= page_x && x0 + x < page_x + page_w) fill(image, x0 + x, line_y + y, text.pixel(x, y)[1], kPageM);
    line_y += text.height_px + 4;
  }
  return image;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  const std::string path = std::string(argv[1]) + "/reading_desk.exr";
  glarelab::ExrWriteOptions options;
  options.write_alpha = false;
  options.write_depth = true;  // float: the depths 0.4, 1 and 3 m exactly as written
  glarelab::write_exr(path, reading_desk(), options);
  std::printf("wrote %s\n", path.c_str());
  return 0;
}
