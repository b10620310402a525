// encoding = "table": a photometer calibration CSV read, refused when malformed (with its place),
// inverted piecewise linearly in luminance, on the CPU and in the encode pass; and the [display]
// keys of the new encodings round-trip through the resolved configuration.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/display_calibration.h"
#include "core/errors.h"
#include "experiment_error.h"
#include "protocols/experiment.h"
#include "runner/display/display_backend.h"
#include "scratch_dir.h"
#include "stimuli/display_model.h"
#include "stimuli/frame_renderer.h"

namespace glarelab {
namespace {

// A measured-looking table in 10-bit code values: black 0.35 cd/m2, white 209.2 cd/m2.
const std::string kMeasured =
    "# photometer readings, one primary at a time, the others at 0\n"
    "code,red_cd_m2,green_cd_m2,blue_cd_m2\n"
    "0,0.35,0.36,0.34\n"
    "128,0.82,1.95,0.52\n"
    "256,2.41,7.30,1.10\n"
    "384,5.32,16.8,2.05\n"
    "512,9.75,31.2,3.61\n"
    "640,15.9,50.9,5.70\n"
    "768,24.1,76.4,8.52\n"
    "896,34.5,108.1,12.0\n"
    "1023,47.2,146.3,16.4\n";
const std::vector<int> kMeasuredCodes = {0, 128, 256, 384, 512, 640, 768, 896, 1023};

// A synthetic table L_c(d) = black + a_c d^2.2 at every 8-bit code (drive column 0..1): its
// inverse is closed form, d = (gain / a_c)^(1 / 2.2).
constexpr double kGamma = 2.2;
constexpr double kBlack = 0.5;
constexpr double kChannelMax[3] = {40.0, 130.0, 15.0};
std::string gamma_table_csv() {
  std::ostringstream csv;
  csv << std::setprecision(17) << "drive,red_cd_m2,green_cd_m2,blue_cd_m2\n";
  for (int code = 0; code <= 255; ++code) {
    const double d = code / 255.0;
    csv << d;
    for (double a : kChannelMax) csv << "," << kBlack + a * std::pow(d, kGamma);
    csv << "\n";
  }
  return csv.str();
}

TEST(DisplayTable, ReadsBlackPeakAndNormalisedDrive) {
  const DisplayCalibration table = parse_display_calibration(kMeasured, "cal.csv");
  ASSERT_EQ(table.rows(), 9u);
  EXPECT_DOUBLE_EQ(table.drive[1], 128.0 / 1023.0);
  EXPECT_EQ(table.drive.back(), 1.0);
  EXPECT_NEAR(table.black_cd_m2(), 0.35, 1e-12);
  EXPECT_NEAR(table.peak_cd_m2(), 0.35 + (47.2 - 0.35) + (146.3 - 0.36) + (16.4 - 0.34), 1e-12);  // 209.2
}

TEST(DisplayTable, InversionReturnsTheMeasuredDriveAtEveryMeasuredPoint) {
  const DisplayCalibration table = parse_display_calibration(kMeasured, "cal.csv");
  for (std::size_t i = 0; i < table.rows(); ++i)
    for (int c = 0; c < 3; ++c) {
      const std::vector<double>& l = table.luminance_cd_m2[static_cast<std::size_t>(c)];
      EXPECT_NEAR(table.drive_for_gain(c, l[i] - l[0]), kMeasuredCodes[i] / 1023.0, 1e-12) << "row " << i;
      EXPECT_NEAR(table.channel_gain_cd_m2(c, kMeasuredCodes[i] / 1023.0), l[i] - l[0], 1e-12);
    }
  // Halfway in luminance between two measured points is halfway in drive (piecewise linear).
  const std::vector<double>& green = table.luminance_cd_m2[1];
  EXPECT_NEAR(table.drive_for_gain(1, 0.5 * (green[3] + green[4]) - green[0]), 448.0 / 1023.0, 1e-12);
  // Beyond the channel's range: clipped to black and full drive.
  EXPECT_EQ(table.drive_for_gain(0, -1.0), 0.0);
  EXPECT_EQ(table.drive_for_gain(0, 1e6), 1.0);
  // An achromatic stimulus of Y cd/m2 shows Y under additivity, clipped to [black, peak].
  for (const double y : {0.35, 3.0, 50.0, 209.2}) {
    const std::array<double, 3> drive = table.drive_for_stimulus({y, y, y});
    double shown = table.black_cd_m2();
    for (int c = 0; c < 3; ++c) shown += table.channel_gain_cd_m2(c, drive[static_cast<std::size_t>(c)]);
    EXPECT_NEAR(shown, y, 1e-9 * y) << y;
  }
  EXPECT_EQ(table.drive_for_stimulus({0.1, 0.1, 0.1})[0], 0.0);
}

TEST(DisplayTable, InversionOfAGammaTableAgainstItsClosedForm) {
  const DisplayCalibration table = parse_display_calibration(gamma_table_csv(), "gamma.csv");
  // Piecewise linear in luminance over 256 rows: the worst drive error is 4.4e-5 (0.045 of a
  // 10-bit code) from drive 0.05 up, 1.1e-3 in the first segment above black (d^2.2 is flat there).
  double worst_above_0p05 = 0.0, worst = 0.0;
  for (int c = 0; c < 3; ++c)
    for (double d = 0.0005; d <= 1.0; d += 0.00073) {
      const double gain = kChannelMax[c] * std::pow(d, kGamma);
      const double error = std::abs(table.drive_for_gain(c, gain) - std::pow(gain / kChannelMax[c], 1.0 / kGamma));
      worst = std::max(worst, error);
      if (d >= 0.05) worst_above_0p05 = std::max(worst_above_0p05, error);
    }
  EXPECT_LT(worst_above_0p05, 4.5e-5);
  EXPECT_LT(worst, 1.2e-3);
  EXPECT_GT(worst, 1e-4);  // the interpolation is not the closed form: the test can see a difference
}

// The encode pass reads the table from a texture and inverts it in the shader.
class TableEncodePass : public ::testing::Test {
 protected:
  static constexpr int kWidth = 64;
  void SetUp() override {
    DisplayRequest request;
    request.width_px = kWidth;
    request.height_px = 4;
    display_ = create_display("offscreen", request);
    renderer_ = std::make_unique<FrameRenderer>(kWidth, 4);
  }
  ImageRGBA encode(const std::vector<std::array<double, 3>>& rgb, const DisplaySpec& spec) {
    ImageRGBA image(kWidth, 4);
    for (std::size_t i = 0; i < rgb.size(); ++i)
      for (int c = 0; c < 3; ++c) image.pixel(static_cast<int>(i), 0)[c] = static_cast<float>(rgb[i][static_cast<std::size_t>(c)]);
    renderer_->replace_stimulus(image);
    renderer_->encode_to_display(spec);
    display_->present();
    return renderer_->read_display();
  }
  std::unique_ptr<DisplayBackend> display_;
  std::unique_ptr<FrameRenderer> renderer_;
};

DisplaySpec table_display(const DisplayCalibration& table, int bits) {
  DisplaySpec spec;
  spec.encoding = DisplayEncoding::table;
  spec.calibration = table;
  spec.peak_luminance_cd_m2 = table.peak_cd_m2();
  spec.bits_per_channel = bits;
  return spec;
}

// The stimulus (per channel, cd/m2) that asks channel c for the gain `gain_cd_m2`.
double stimulus_for_gain(const DisplayCalibration& table, int c, double gain_cd_m2) {
  const std::vector<double>& l = table.luminance_cd_m2[static_cast<std::size_t>(c)];
  return table.black_cd_m2() + (table.peak_cd_m2() - table.black_cd_m2()) * gain_cd_m2 / (l.back() - l.front());
}

TEST_F(TableEncodePass, TenBitCodesAtAndBetweenTheMeasuredPoints) {
  const DisplayCalibration table = parse_display_calibration(kMeasured, "cal.csv");
  std::vector<std::array<double, 3>> rgb;
  std::vector<double> expected_codes;
  for (std::size_t i = 0; i < table.rows(); ++i) {
    std::array<double, 3> at{}, between{};
    for (int c = 0; c < 3; ++c) {
      const std::vector<double>& l = table.luminance_cd_m2[static_cast<std::size_t>(c)];
      at[static_cast<std::size_t>(c)] = stimulus_for_gain(table, c, l[i] - l[0]);
      if (i + 1 < table.rows()) between[static_cast<std::size_t>(c)] = stimulus_for_gain(table, c, 0.5 * (l[i] + l[i + 1]) - l[0]);
    }
    rgb.push_back(at);
    expected_codes.push_back(kMeasuredCodes[i]);
    if (i + 1 < table.rows()) {
      rgb.push_back(between);
      expected_codes.push_back(0.5 * (kMeasuredCodes[i] + kMeasuredCodes[i + 1]));
    }
  }
  const ImageRGBA shown = encode(rgb, table_display(table, 10));
  for (std::size_t i = 0; i < rgb.size(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_LE(std::abs(shown.pixel(static_cast<int>(i), 0)[c] * 1023.0 - expected_codes[i]), 1.0)
          << "point " << i << " channel " << c;
}

TEST_F(TableEncodePass, TenBitCodesOfTheGammaTableAgainstItsClosedForm) {
  const DisplayCalibration table = parse_display_calibration(gamma_table_csv(), "gamma.csv");
  std::vector<std::array<double, 3>> rgb;
  std::vector<double> drives;
  for (int i = 0; i < kWidth; ++i) {
    const double d = 0.05 + 0.95 * i / (kWidth - 1.0);
    drives.push_back(d);
    std::array<double, 3> s{};
    for (int c = 0; c < 3; ++c) s[static_cast<std::size_t>(c)] = stimulus_for_gain(table, c, kChannelMax[c] * std::pow(d, kGamma));
    rgb.push_back(s);
  }
  const ImageRGBA shown = encode(rgb, table_display(table, 10));
  for (int i = 0; i < kWidth; ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_LE(std::abs(std::lround(shown.pixel(i, 0)[c] * 1023.0) - std::lround(drives[static_cast<std::size_t>(i)] * 1023.0)), 1)
          << "drive " << drives[static_cast<std::size_t>(i)] << " channel " << c;
}

TEST_F(TableEncodePass, EightBitDitherReproducesASubCodeLuminance) {
  const DisplayCalibration table = parse_display_calibration(gamma_table_csv(), "gamma.csv");
  // Green between codes 60 and 61, 40 % of the way in luminance; a 4x4 cell's mean gain is the
  // wanted gain to 1/32 of the step (thresholds (i + 0.5) / 16: 6 of 16 pixels take code 61).
  const double low = kChannelMax[1] * std::pow(60 / 255.0, kGamma), high = kChannelMax[1] * std::pow(61 / 255.0, kGamma);
  const double wanted = low + 0.4 * (high - low);
  const double s = stimulus_for_gain(table, 1, wanted);
  ImageRGBA image(kWidth, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < kWidth; ++x) image.pixel(x, y)[1] = static_cast<float>(s);
  renderer_->replace_stimulus(image);
  renderer_->encode_to_display(table_display(table, 8));
  const ImageRGBA shown = renderer_->read_display();
  for (int cell = 0; cell < kWidth / 4; ++cell) {
    double sum = 0.0;
    int high_count = 0;
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) {
        const long code = std::lround(shown.pixel(cell * 4 + x, y)[1] * 255.0);
        ASSERT_TRUE(code == 60 || code == 61) << code;
        high_count += code == 61;
        sum += kChannelMax[1] * std::pow(static_cast<double>(code) / 255.0, kGamma);
      }
    EXPECT_EQ(high_count, 6);
    EXPECT_NEAR(sum / 16.0, wanted, (high - low) / 32.0);
  }
}

std::string refusal(const std::string& csv) {
  try {
    parse_display_calibration(csv, "cal.csv");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

TEST(DisplayTable, BadFilesAreRefusedAtTheirPlace) {
  const std::string header = "drive,red_cd_m2,green_cd_m2,blue_cd_m2\n";
  // Non-monotonic: green falls on line 4, whose green value starts at column 5.
  EXPECT_NE(refusal(header + "0,0.1,0.1,0.1\n0.5,5,20,2\n1,9,19.5,4\n").find(
                "cal.csv:4:5: display calibration: non-monotonic luminance: 'green_cd_m2' falls from 20 to 19.5"),
            std::string::npos)
      << refusal(header + "0,0.1,0.1,0.1\n0.5,5,20,2\n1,9,19.5,4\n");
  EXPECT_NE(refusal(header + "0,0.1,0.1,0.1\n").find("cal.csv:2: display calibration: at least 2 rows"), std::string::npos)
      << refusal(header + "0,0.1,0.1,0.1\n");
  EXPECT_NE(refusal(header + "0,0.1,0.1,0.1\n1,9,-2,4\n").find("cal.csv:3:5: display calibration: column 'green_cd_m2': negative value -2"),
            std::string::npos)
      << refusal(header + "0,0.1,0.1,0.1\n1,9,-2,4\n");
  EXPECT_NE(refusal("drive,red_cd_m2,green_cd_m2\n0,1,1\n1,2,2\n").find("cal.csv:1:28: display calibration: missing column 'blue_cd_m2'"),
            std::string::npos)
      << refusal("drive,red_cd_m2,green_cd_m2\n0,1,1\n1,2,2\n");
  EXPECT_NE(refusal(header + "0,0.1,0.1,0.1\n1,9,20\n").find("cal.csv:3:7: display calibration: missing column 'blue_cd_m2'"),
            std::string::npos)
      << refusal(header + "0,0.1,0.1,0.1\n1,9,20\n");
  EXPECT_NE(refusal(header + "0,0.1,0.1,0.1\n1,9,2O,4\n").find("cal.csv:3:5: display calibration: column 'green_cd_m2': expected a number, found '2O'"),
            std::string::npos);
  EXPECT_NE(refusal(header + "0.1,0.1,0.1,0.1\n1,9,20,4\n").find("cal.csv:2:1: display calibration: the first row must be drive 0"),
            std::string::npos);
  EXPECT_NE(refusal(header + "0,0.1,0.1,0.1\n0.5,5,10,2\n0.5,9,20,4\n").find("cal.csv:4:1: display calibration: drive levels must rise"),
            std::string::npos);
  EXPECT_NE(refusal(header + "0,0.1,0.1,0.1\n0.9,9,20,4\n").find("cal.csv:3:1: display calibration: the last row must be full drive 1"),
            std::string::npos);
  EXPECT_NE(refusal(header + "0,0.1,0.1,0.1\n255,9,20,4\n").find("cal.csv:3:1: display calibration: column 'drive': 255 above full drive 1"),
            std::string::npos);
  EXPECT_NE(refusal("code,red_cd_m2,green_cd_m2,blue_cd_m2,white_cd_m2\n").find("cal.csv:1:39: display calibration: unknown column 'white_cd_m2'"),
            std::string::npos);
  EXPECT_NE(refusal(header + "0,0.1,0.1,0.1\n1,9,0.1,4\n").find("cal.csv:3:5: display calibration: 'green_cd_m2' does not rise"),
            std::string::npos);
  EXPECT_NE(refusal("# nothing measured\n").find("cal.csv: display calibration: empty file"), std::string::npos);
  // Comments, blank lines, CRLF and columns in another order are accepted.
  const DisplayCalibration table =
      parse_display_calibration("# lab 3\r\n\r\nblue_cd_m2, code ,red_cd_m2,green_cd_m2\r\n0.1,0,0.2,0.3\r\n4,255,9,20\r\n", "cal.csv");
  EXPECT_EQ(table.luminance_cd_m2[2].back(), 4.0);
  EXPECT_EQ(table.drive.back(), 1.0);
}

// An experiment file's [display] with the new keys; lines 1-13 fixed, the [display] keys from line 14.
std::string experiment_with_display(const std::string& display) {
  return "[experiment]\nname = \"display keys\"\n\n[scenes]\na = { file = \"a.exr\" }\nb = { file = \"b.exr\" }\n"
         "[procedure]\ntype = \"forced_choice\"\n\n[conditions]\nrows = [{ scene_a = \"a\", scene_b = \"b\" }]\n\n"
         "[display]\n" + display;
}

TEST(DisplayTableKeys, RoundTripThroughTheResolvedConfig) {
  test::ScratchDir dir;
  dir.write("cal.csv", kMeasured);
  for (const std::string& display :
       {std::string("encoding = \"table\"\ncalibration = \"cal.csv\"\nbits_per_channel = 10\n"),
        std::string("encoding = \"pq\"\nprimaries = \"bt2020\"\npeak_luminance_cd_m2 = 1000.0\nbits_per_channel = 16\n"),
        std::string("encoding = \"srgb\"\nbits_per_channel = 8\n")}) {
    const std::string path = dir.write("exp.toml", experiment_with_display(display));
    const Experiment original = load_experiment(path);
    const std::string resolved = resolved_config_toml(original);
    const Experiment reread = parse_experiment_text(resolved, "<stored config>", "/");
    EXPECT_EQ(resolved_config_toml(reread), resolved);
    EXPECT_EQ(reread.display.encoding, original.display.encoding);
    EXPECT_EQ(reread.display.primaries, original.display.primaries);
    EXPECT_EQ(reread.display.bits_per_channel, original.display.bits_per_channel);
    EXPECT_EQ(reread.display.peak_luminance_cd_m2, original.display.peak_luminance_cd_m2);
    EXPECT_EQ(reread.display.calibration.drive, original.display.calibration.drive);
    EXPECT_EQ(reread.display.calibration.luminance_cd_m2, original.display.calibration.luminance_cd_m2);
  }
  const Experiment table = load_experiment(dir.write("exp.toml", experiment_with_display(
                                                                     "encoding = \"table\"\ncalibration = \"cal.csv\"\n")));
  EXPECT_EQ(table.display.calibration.file, dir.file("cal.csv"));
  EXPECT_NEAR(table.display.peak_luminance_cd_m2, 209.2, 1e-9);  // the peak comes from the table
  const Experiment pq = load_experiment(dir.write("exp.toml", experiment_with_display("encoding = \"pq\"\n")));
  EXPECT_EQ(pq.display.primaries, DisplayPrimaries::rec709);
  EXPECT_EQ(pq.display.bits_per_channel, 0);
}

TEST(DisplayTableKeys, RefusedAtTheirKey) {
  test::ScratchDir dir;
  dir.write("cal.csv", kMeasured);
  dir.write("bad.csv", "code,red_cd_m2,green_cd_m2,blue_cd_m2\n0,1,1,1\n255,2,-2,2\n");
  const auto error = [&](const std::string& display) {
    return test::experiment_error(dir.write("exp.toml", experiment_with_display(display)));
  };
  const std::string exp = dir.file("exp.toml");
  EXPECT_NE(error("encoding = \"table\"\ncalibration = \"cal.csv\"\npeak_luminance_cd_m2 = 250.0\n")
                .find(exp + ":16:24: key 'display.peak_luminance_cd_m2': contradicts the calibration table's peak 209.2"),
            std::string::npos)
      << error("encoding = \"table\"\ncalibration = \"cal.csv\"\npeak_luminance_cd_m2 = 250.0\n");
  EXPECT_EQ(error("encoding = \"table\"\ncalibration = \"cal.csv\"\npeak_luminance_cd_m2 = 210.0\n"), "no error");  // within 1 %
  EXPECT_NE(error("encoding = \"table\"\n").find("needs calibration"), std::string::npos);
  EXPECT_NE(error("encoding = \"table\"\ncalibration = \"none.csv\"\n").find(exp + ":15:15: key 'display.calibration': no calibration file"),
            std::string::npos)
      << error("encoding = \"table\"\ncalibration = \"none.csv\"\n");
  EXPECT_NE(error("encoding = \"table\"\ncalibration = \"bad.csv\"\n").find(dir.file("bad.csv") + ":3:7: display calibration: column 'green_cd_m2': negative value"),
            std::string::npos)
      << error("encoding = \"table\"\ncalibration = \"bad.csv\"\n");
  EXPECT_NE(error("calibration = \"cal.csv\"\n").find("applies only to encoding = 'table'"), std::string::npos);
  EXPECT_NE(error("primaries = \"bt2020\"\n").find("applies only to encoding = 'pq'"), std::string::npos);
  EXPECT_NE(error("encoding = \"pq\"\nprimaries = \"p3\"\n").find("unsupported primaries 'p3'"), std::string::npos);
  EXPECT_NE(error("encoding = \"pq\"\npeak_luminance_cd_m2 = 12000.0\n").find("peak_luminance_cd_m2"), std::string::npos);
  EXPECT_NE(error("bits_per_channel = 12\n").find(exp + ":14:20: key 'display.bits_per_channel': must be 8, 10 or 16"),
            std::string::npos)
      << error("bits_per_channel = 12\n");
  EXPECT_NE(error("encoding = \"hlg\"\n").find("supported: 'srgb', 'gamma', 'pq', 'table'"), std::string::npos);
}

}  // namespace
}  // namespace glarelab
