// SMPTE ST 2084 (PQ) encoding, framebuffer depths and ordered dithering, through the encode pass
// of the frame renderer on the offscreen backend, read back and compared with closed forms
// computed here in double (not with the project's own PQ code).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "runner/display/display_backend.h"
#include "stimuli/display_model.h"
#include "stimuli/frame_renderer.h"

namespace glarelab {
namespace {

// SMPTE ST 2084:2014 inverse EOTF, full-range signal in [0, 1] (constants of the standard, 5.3).
double st2084_signal(double luminance_cd_m2) {
  const double m1 = 2610.0 / 16384.0, m2 = 2523.0 / 4096.0 * 128.0;
  const double c1 = 3424.0 / 4096.0, c2 = 2413.0 / 4096.0 * 32.0, c3 = 2392.0 / 4096.0 * 32.0;
  const double y_m1 = std::pow(luminance_cd_m2 / 10000.0, m1);
  return std::pow((c1 + c2 * y_m1) / (1.0 + c3 * y_m1), m2);
}

double srgb_linear(double encoded) {  // IEC 61966-2-1 decoding
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

// Renders `luminances` (achromatic, cd/m2), one per pixel along row 0 of a 64-wide frame, or the
// RGB triples of `rgb` when given, and returns the drive values read back.
constexpr int kWidth = 64;
constexpr int kHeight = 16;

class EncodePass : public ::testing::Test {
 protected:
  void SetUp() override {
    DisplayRequest request;
    request.width_px = kWidth;
    request.height_px = kHeight;
    display_ = create_display("offscreen", request);
    renderer_ = std::make_unique<FrameRenderer>(kWidth, kHeight);
  }
  ImageRGBA encode(const ImageRGBA& stimulus, const DisplaySpec& spec) {
    renderer_->replace_stimulus(stimulus);
    renderer_->encode_to_display(spec);
    display_->present();
    return renderer_->read_display();
  }
  static ImageRGBA row_of(const std::vector<std::array<double, 3>>& rgb) {
    ImageRGBA image(kWidth, kHeight);
    for (std::size_t i = 0; i < rgb.size(); ++i)
      for (int c = 0; c < 3; ++c) image.pixel(static_cast<int>(i), 0)[c] = static_cast<float>(rgb[i][static_cast<std::size_t>(c)]);
    return image;
  }
  std::unique_ptr<DisplayBackend> display_;
  std::unique_ptr<FrameRenderer> renderer_;
};

DisplaySpec pq_display(double peak_cd_m2, int bits, DisplayPrimaries primaries = DisplayPrimaries::rec709) {
  DisplaySpec spec;
  spec.encoding = DisplayEncoding::pq;
  spec.peak_luminance_cd_m2 = peak_cd_m2;
  spec.bits_per_channel = bits;
  spec.primaries = primaries;
  return spec;
}

int code_of(float drive, int max_code) { return static_cast<int>(std::lround(static_cast<double>(drive) * max_code)); }

TEST(DisplayPq, CpuModelIsTheClosedForm) {
  const DisplayModel model(pq_display(10000.0, 10));
  for (double luminance = 0.005; luminance <= 10000.0; luminance *= 1.7)
    EXPECT_NEAR(model.encode(luminance), st2084_signal(luminance), 1e-12) << luminance << " cd/m2";
  EXPECT_NEAR(pq_decode(st2084_signal(123.4)), 123.4, 1e-9);
  EXPECT_EQ(model.encode(0.0), std::pow(3424.0 / 4096.0, 2523.0 / 4096.0 * 128.0));  // c1^m2: ~7.3e-7, not 0
}

TEST_F(EncodePass, TenBitPqMatchesTheClosedFormFrom0p005To10000) {
  std::vector<std::array<double, 3>> rgb;
  for (int i = 0; i < kWidth; ++i) {
    const double luminance = 0.005 * std::pow(10000.0 / 0.005, i / static_cast<double>(kWidth - 1));  // log steps
    rgb.push_back({luminance, luminance, luminance});
  }
  const ImageRGBA shown = encode(row_of(rgb), pq_display(10000.0, 10));
  int worst = 0;
  for (int i = 0; i < kWidth; ++i)
    for (int c = 0; c < 3; ++c) {
      const double expected = st2084_signal(rgb[static_cast<std::size_t>(i)][0]) * 1023.0;
      const float drive = shown.pixel(i, 0)[c];
      // A 10-bit target holds exactly code / 1023.
      ASSERT_NEAR(drive * 1023.0, std::round(drive * 1023.0), 1e-3) << "pixel " << i;
      const int error = std::abs(code_of(drive, 1023) - static_cast<int>(std::lround(expected)));
      worst = std::max(worst, error);
      ASSERT_LE(error, 1) << rgb[static_cast<std::size_t>(i)][0] << " cd/m2: code " << code_of(drive, 1023)
                          << ", closed form " << expected;
    }
  RecordProperty("worst_code_error", worst);
}

TEST_F(EncodePass, PublishedFullRangeTenBitCodes) {
  // Full-range 10-bit PQ (code = round(1023 N)); narrow range would be 64 + 876 N (509 and 723).
  const ImageRGBA shown = encode(row_of({{0, 0, 0}, {100, 100, 100}, {1000, 1000, 1000}, {10000, 10000, 10000}}),
                                 pq_display(10000.0, 10));
  EXPECT_EQ(code_of(shown.pixel(0, 0)[1], 1023), 0);
  EXPECT_EQ(code_of(shown.pixel(1, 0)[1], 1023), 520);
  EXPECT_EQ(code_of(shown.pixel(2, 0)[1], 1023), 769);
  EXPECT_EQ(code_of(shown.pixel(3, 0)[1], 1023), 1023);
}

TEST_F(EncodePass, PqClipsAtTheDisplaysPeak) {
  const ImageRGBA shown = encode(row_of({{4000, 4000, 4000}, {999, 999, 999}}), pq_display(1000.0, 10));
  EXPECT_EQ(code_of(shown.pixel(0, 0)[0], 1023), 769);  // 4000 shown as the 1000 cd/m2 peak
  EXPECT_EQ(code_of(shown.pixel(1, 0)[0], 1023), static_cast<int>(std::lround(st2084_signal(999.0) * 1023.0)));
}

TEST_F(EncodePass, Bt2020PrimariesUseTheBt2087Matrix) {
  // ITU-R BT.2087-0 Eq. 2, typed here from the Recommendation.
  const double m[3][3] = {{0.6274, 0.3293, 0.0433}, {0.0691, 0.9195, 0.0114}, {0.0164, 0.0880, 0.8956}};
  const std::vector<std::array<double, 3>> rgb = {{100, 0, 0}, {0, 100, 0}, {0, 0, 100}, {30, 200, 5}};
  const ImageRGBA shown = encode(row_of(rgb), pq_display(1000.0, 10, DisplayPrimaries::bt2020));
  for (std::size_t i = 0; i < rgb.size(); ++i)
    for (int r = 0; r < 3; ++r) {
      const double bt2020 = m[r][0] * rgb[i][0] + m[r][1] * rgb[i][1] + m[r][2] * rgb[i][2];
      EXPECT_LE(std::abs(code_of(shown.pixel(static_cast<int>(i), 0)[r], 1023) -
                         static_cast<int>(std::lround(st2084_signal(bt2020) * 1023.0))), 1)
          << "colour " << i << " channel " << r;
    }
}

TEST_F(EncodePass, HalfFloatTargetKeepsElevenSignificantBits) {
  std::vector<std::array<double, 3>> rgb;
  for (int i = 0; i < kWidth; ++i) {
    const double luminance = 0.01 * std::pow(1e5, i / static_cast<double>(kWidth - 1));
    rgb.push_back({luminance, luminance, luminance});
  }
  const ImageRGBA shown = encode(row_of(rgb), pq_display(1000.0, 16));
  for (int i = 0; i < kWidth; ++i) {
    const double expected = st2084_signal(std::min(rgb[static_cast<std::size_t>(i)][0], 1000.0));
    // Half float: 11 significant bits, plus the float shader's own error.
    EXPECT_NEAR(shown.pixel(i, 0)[1], expected, std::ldexp(expected, -10) + 1e-5) << rgb[static_cast<std::size_t>(i)][0];
  }
}

// 8 bits with the 4x4 Bayer dither: a luminance between two code values is shown as a mix of the
// two whose mean over each 4x4 cell is the luminance, to 1/32 of a code step.
void check_dither_cells(const ImageRGBA& shown, double wanted, int low_code, double low, double high,
                        const std::function<double(int)>& luminance_of_code) {
  for (int cell_y = 0; cell_y < 4; ++cell_y)
    for (int cell_x = 0; cell_x < kWidth / 4; ++cell_x) {
      double sum = 0.0;
      int high_count = 0;
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
          const int code = code_of(shown.pixel(cell_x * 4 + x, cell_y * 4 + y)[0], 255);
          ASSERT_TRUE(code == low_code || code == low_code + 1) << "code " << code << " around " << low_code;
          high_count += code == low_code + 1;
          sum += luminance_of_code(code);
        }
      const double fraction = (wanted - low) / (high - low);
      EXPECT_EQ(high_count, static_cast<int>(std::ceil(fraction * 16.0 - 0.5)));  // thresholds (i + 0.5) / 16
      EXPECT_NEAR(sum / 16.0, wanted, (high - low) / 32.0 + 1e-9 * wanted) << "cell " << cell_x << "," << cell_y;
    }
}

ImageRGBA uniform_frame(double luminance) {
  ImageRGBA image(kWidth, kHeight);
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < image.width_px; ++x)
      for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = static_cast<float>(luminance);
  return image;
}

TEST_F(EncodePass, EightBitDitherReproducesASubCodeLuminance) {
  DisplaySpec spec;
  spec.encoding = DisplayEncoding::srgb;
  spec.peak_luminance_cd_m2 = 100.0;
  spec.bits_per_channel = 8;
  const auto luminance_of_code = [](int code) { return 100.0 * srgb_linear(code / 255.0); };
  for (const double fraction : {0.3, 0.71}) {
    const int low_code = 40;
    const double low = luminance_of_code(low_code), high = luminance_of_code(low_code + 1);
    const double wanted = low + fraction * (high - low);
    check_dither_cells(encode(uniform_frame(wanted), spec), wanted, low_code, low, high, luminance_of_code);
  }
  // Without dithering (the backend's own float framebuffer) the same frame is one flat drive value.
  spec.bits_per_channel = 0;
  const ImageRGBA flat = encode(uniform_frame(luminance_of_code(40) + 0.3 * (luminance_of_code(41) - luminance_of_code(40))), spec);
  EXPECT_EQ(flat.pixel(0, 0)[0], flat.pixel(1, 0)[0]);
}

TEST_F(EncodePass, EightBitDitherOfPq) {
  const DisplaySpec spec = pq_display(1000.0, 8);
  const auto luminance_of_code = [](int code) { return pq_decode(code / 255.0); };
  const int low_code = 100;
  const double low = luminance_of_code(low_code), high = luminance_of_code(low_code + 1);
  const double wanted = low + 0.55 * (high - low);
  ASSERT_NEAR(st2084_signal(low), low_code / 255.0, 1e-9);  // pq_decode inverts the closed form
  check_dither_cells(encode(uniform_frame(wanted), spec), wanted, low_code, low, high, luminance_of_code);
}

}  // namespace
}  // namespace glarelab

namespace glarelab {
namespace {

// The window backend asks GLFW for the depth and reads back what it got. Xvfb's 24-bit screen
// offers 8 bits per channel: 8 opens (and says so in the platform text the session log keeps),
// 10 is refused naming the depth achieved.
TEST(WindowBackend, FramebufferDepthIsCheckedAfterCreation) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  DisplayRequest request;
  request.width_px = 32;
  request.height_px = 16;
  request.visible = false;
  request.bits_per_channel = 8;
  {
    auto display = create_display("window", request);
    EXPECT_NE(display->gl_info().platform.find("GLFW window, 8/8/8 bits framebuffer"), std::string::npos)
        << display->gl_info().platform;
  }
  request.bits_per_channel = 10;
  try {
    create_display("window", request);
    FAIL() << "a 10-bit window opened on an 8-bit screen";
  } catch (const DisplayError& error) {
    EXPECT_NE(std::string(error.what()).find("GLFW: [display] bits_per_channel = 10 requested, but the window's "
                                             "framebuffer has 8/8/8 bits per channel"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace glarelab
