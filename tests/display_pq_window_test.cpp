// PQ through the window backend (GLFW under Xvfb, an 8-bit screen): the encode pass draws into the
// window's own framebuffer, read back before the swap and compared with SMPTE ST 2084 computed here
// in double. At 8 bits the ordered dither puts each pixel on the code below or above the exact
// value, so every pixel is within one code; a uniform 4 x 4 cell averages to the exact value
// within 1/32 of a code (docs/DISPLAY_CALIBRATION.md).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

#include "runner/display/display_backend.h"
#include "stimuli/display_model.h"
#include "stimuli/frame_renderer.h"

namespace glarelab {
namespace {

double st2084_signal(double luminance_cd_m2) {  // SMPTE ST 2084:2014 inverse EOTF, full range
  const double m1 = 2610.0 / 16384.0, m2 = 2523.0 / 4096.0 * 128.0;
  const double c1 = 3424.0 / 4096.0, c2 = 2413.0 / 4096.0 * 32.0, c3 = 2392.0 / 4096.0 * 32.0;
  const double y_m1 = std::pow(luminance_cd_m2 / 10000.0, m1);
  return std::pow((c1 + c2 * y_m1) / (1.0 + c3 * y_m1), m2);
}

TEST(WindowBackend, PqReadBackFromTheWindowIsTheClosedFormWithinOneCodeAtEightBits) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  constexpr int kWidth = 64, kHeight = 16;
  DisplayRequest request;
  request.width_px = kWidth;
  request.height_px = kHeight;
  request.visible = false;
  request.bits_per_channel = 8;
  const std::unique_ptr<DisplayBackend> display = create_display("window", request);
  FrameRenderer renderer(kWidth, kHeight);
  DisplaySpec spec;
  spec.encoding = DisplayEncoding::pq;
  spec.peak_luminance_cd_m2 = 10000.0;
  spec.bits_per_channel = 8;
  // Rows 0-3: one luminance per column, log steps from 0.005 to 10000 cd/m2; rows 4-15: 130 cd/m2 (code 136.33).
  ImageRGBA stimulus(kWidth, kHeight);
  std::vector<double> column_cd_m2;
  for (int x = 0; x < kWidth; ++x) {
    column_cd_m2.push_back(0.005 * std::pow(10000.0 / 0.005, x / static_cast<double>(kWidth - 1)));
    for (int y = 0; y < kHeight; ++y)
      for (int c = 0; c < 3; ++c)
        stimulus.pixel(x, y)[c] = static_cast<float>(y < 4 ? column_cd_m2.back() : 130.0);
  }
  renderer.replace_stimulus(stimulus);
  renderer.encode_to_display(spec);
  const ImageRGBA shown = renderer.read_display();  // the back buffer, before the swap
  display->present();
  ASSERT_EQ(shown.width_px, kWidth);
  int worst = 0;
  for (int x = 0; x < kWidth; ++x)
    for (int y = 0; y < 4; ++y)
      for (int c = 0; c < 3; ++c) {
        const double exact_code = st2084_signal(column_cd_m2[static_cast<std::size_t>(x)]) * 255.0;
        const double code = static_cast<double>(shown.pixel(x, y)[c]) * 255.0;
        ASSERT_NEAR(code, std::round(code), 1e-3) << "an 8-bit framebuffer holds whole codes";
        ASSERT_LE(std::abs(code - exact_code), 1.0) << column_cd_m2[static_cast<std::size_t>(x)] << " cd/m2, pixel "
                                                    << x << "," << y << ": code " << code << ", exact " << exact_code;
        worst = std::max(worst, static_cast<int>(std::ceil(std::abs(code - exact_code))));
      }
  // The uniform patch: each 4 x 4 cell's mean code is the exact code within 1/32.
  const double patch_code = st2084_signal(130.0) * 255.0;
  ASSERT_GT(std::abs(patch_code - std::round(patch_code)), 0.1) << "the patch should fall between two codes";
  for (int cell_x = 0; cell_x < kWidth; cell_x += 4)
    for (int cell_y = 4; cell_y + 4 <= kHeight; cell_y += 4) {
      double sum = 0.0;
      for (int y = cell_y; y < cell_y + 4; ++y)
        for (int x = cell_x; x < cell_x + 4; ++x) sum += static_cast<double>(shown.pixel(x, y)[1]) * 255.0;
      EXPECT_NEAR(sum / 16.0, patch_code, 1.0 / 32.0 + 1e-6) << "cell at " << cell_x << "," << cell_y;
    }
  RecordProperty("worst_code_error", worst);
}

}  // namespace
}  // namespace glarelab
