// `glarelab calibrate` offscreen with --measurements, as a user runs it: a simulated display of
// known gamma and peak measured at the codes the command shows gives back that gamma and peak, the
// CSV it writes loads through `encoding = "table"` and inverts to the closed form, the patches are
// the codes the table says; bad readings are refused (exit 2) with nothing written.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/display_calibration.h"
#include "core/exr_io.h"
#include "core/png_io.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

// A display with gamma 2.2 and a white of 250 cd/m2 over a black of 0.2 cd/m2, its primaries
// sharing the gain in the Rec.709 luminance proportions (ITU-R BT.709-6, item 3.2).
constexpr double kGamma = 2.2;
constexpr double kWhite_cd_m2 = 250.0;
constexpr double kBlack_cd_m2 = 0.2;
constexpr double kShare[4] = {0.2126, 0.7152, 0.0722, 1.0};  // red, green, blue, white

double simulated_cd_m2(int channel, double drive) {
  return kBlack_cd_m2 + kShare[channel] * (kWhite_cd_m2 - kBlack_cd_m2) * std::pow(drive, kGamma);
}

// The code level i of n is sent as at `full_code` (255 or 1023), worked out here independently
// of the command: the nearest code to i / (n - 1) of full drive.
int code_of(int level, int levels, int full_code) {
  return static_cast<int>(std::lround(static_cast<double>(level) * full_code / (levels - 1)));
}

// The photometer's readings of every patch in the order shown: red, green, blue, white.
std::string simulated_readings(int levels, int full_code) {
  std::string text = "# simulated photometer: gamma 2.2, 250 cd/m2 white, 0.2 cd/m2 black\n";
  char value[64];
  for (int channel = 0; channel < 4; ++channel) {
    for (int level = 0; level < levels; ++level) {
      std::snprintf(value, sizeof value, "%.17g\n",
                    simulated_cd_m2(channel, static_cast<double>(code_of(level, levels, full_code)) / full_code));
      text += value;
    }
  }
  return text;
}

// "  red    black 0.2 cd/m2  peak 53.2425 cd/m2  gamma 2.2000 (...)": the numbers of one channel's line.
struct ReportedFit {
  double black_cd_m2 = -1, peak_cd_m2 = -1, gamma = -1;
};
ReportedFit reported_fit(const std::string& output, const std::string& channel) {
  const std::regex line("  " + channel + " +black ([0-9.e+-]+) cd/m2  peak ([0-9.e+-]+) cd/m2  gamma ([0-9.]+)");
  std::smatch match;
  ReportedFit fit;
  if (std::regex_search(output, match, line)) {
    fit.black_cd_m2 = std::stod(match[1]);
    fit.peak_cd_m2 = std::stod(match[2]);
    fit.gamma = std::stod(match[3]);
  }
  return fit;
}

TEST(CalibrateCommand, SimulatedGamma22DisplayGivesBackGammaPeakAndATableThatInvertsToTheClosedForm) {
  const test::ScratchDir dir;
  const int levels = 17;
  const std::string readings = dir.write("readings.txt", simulated_readings(levels, 255));
  const std::string table = dir.file("display.csv");
  const auto run = test::run_glarelab({"calibrate", "--display", "offscreen", "--width", "40", "--height", "30",
                                       "--measurements", readings, "--out", table, "--save-patches",
                                       dir.file("patches")},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;

  // Reported: printed to 4 decimals, so gamma 2.2 to half a unit of the last place; the fit itself
  // is exact for a pure power law (the black is subtracted before the logarithm).
  for (const auto& [channel, index] : std::vector<std::pair<std::string, int>>{{"red", 0}, {"green", 1}, {"blue", 2}, {"white", 3}}) {
    const ReportedFit fit = reported_fit(run.output, channel);
    EXPECT_NEAR(fit.gamma, kGamma, 5e-5) << channel << "\n" << run.output;
    EXPECT_NEAR(fit.black_cd_m2, kBlack_cd_m2, 1e-6) << channel;
    EXPECT_NEAR(fit.peak_cd_m2, simulated_cd_m2(index, 1.0), 1e-3 * simulated_cd_m2(index, 1.0)) << channel;
  }
  EXPECT_THAT(run.output,
              ::testing::HasSubstr("peak 250 cd/m2 (black + the three gains); white measured 250 cd/m2 ("));

  // The CSV loads through the table encoding's reader: codes over 255, the readings as measured.
  const DisplayCalibration calibration = read_display_calibration(table);
  ASSERT_EQ(calibration.rows(), static_cast<std::size_t>(levels));
  for (int level = 0; level < levels; ++level) {
    const double drive = static_cast<double>(code_of(level, levels, 255)) / 255.0;
    EXPECT_DOUBLE_EQ(calibration.drive[static_cast<std::size_t>(level)], drive) << level;
    for (int channel = 0; channel < 3; ++channel)
      EXPECT_EQ(calibration.luminance_cd_m2[static_cast<std::size_t>(channel)][static_cast<std::size_t>(level)],
                simulated_cd_m2(channel, drive))
          << "the CSV keeps every reading exactly; channel " << channel << " level " << level;
  }
  EXPECT_NEAR(calibration.peak_cd_m2(), kWhite_cd_m2, 1e-9);
  EXPECT_NEAR(calibration.black_cd_m2(), kBlack_cd_m2, 1e-12);
  // An achromatic stimulus inverted through the table against the closed form of the simulated
  // display, d = ((Y - black) / (white - black))^(1 / 2.2): between the 17 measured levels the
  // inversion is linear in luminance, off the power law by 3.46e-3 of full drive at most from 5 cd/m2
  // up (NumPy's interp of the same points and luminances gives the same; largest in the lowest
  // segments, where d^2.2 bends most).
  double worst = 0.0;
  for (double y_cd_m2 = 5.0; y_cd_m2 <= 250.0; y_cd_m2 += 5.0) {
    const std::array<double, 3> drive = calibration.drive_for_stimulus({y_cd_m2, y_cd_m2, y_cd_m2});
    const double closed_form = std::pow((y_cd_m2 - kBlack_cd_m2) / (kWhite_cd_m2 - kBlack_cd_m2), 1.0 / kGamma);
    for (double d : drive) worst = std::max(worst, std::abs(d - closed_form));
  }
  EXPECT_LT(worst, 3.5e-3);
  std::printf("table inversion against the closed form, 5-250 cd/m2: max |drive error| %.3g of full drive\n", worst);

  // The patches shown were the codes the table records: red level 5 is (code, 0, 0) everywhere,
  // white level 16 is full white; 68 patches in all.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.file("patches"))) ++files;
  EXPECT_EQ(files, 4 * levels);
  const ImageRGBA red5 = read_png_encoded(dir.file("patches/005_red_level05.png"));
  const float red_code = static_cast<float>(code_of(5, levels, 255)) / 255.0f;
  for (const auto& [x, y] : std::vector<std::pair<int, int>>{{0, 0}, {20, 15}, {39, 29}}) {
    EXPECT_FLOAT_EQ(red5.pixel(x, y)[0], red_code);
    EXPECT_FLOAT_EQ(red5.pixel(x, y)[1], 0.0f);
    EXPECT_FLOAT_EQ(red5.pixel(x, y)[2], 0.0f);
  }
  const ImageRGBA white = read_png_encoded(dir.file("patches/067_white_level16.png"));
  for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(white.pixel(20, 15)[c], 1.0f);
}

TEST(CalibrateCommand, TenBitLevelsAreWholeCodesOf1023AndACentredPatchLeavesTheSurroundBlack) {
  const test::ScratchDir dir;
  const int levels = 5;
  const std::string table = dir.file("display10.csv");
  const auto run = test::run_glarelab(
      {"calibrate", "--display", "offscreen", "--width", "40", "--height", "20", "--levels", "5", "--bits-per-channel",
       "10", "--patch-fraction", "0.5", "--measurements", dir.write("r.txt", simulated_readings(levels, 1023)), "--out",
       table, "--save-patches", dir.file("patches")},
      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(test::read_bytes(table), ::testing::HasSubstr("\ncode,red_cd_m2,green_cd_m2,blue_cd_m2\n0,"));
  const DisplayCalibration calibration = read_display_calibration(table);
  ASSERT_EQ(calibration.rows(), 5u);
  EXPECT_DOUBLE_EQ(calibration.drive[1], 256.0 / 1023.0);  // 1023 / 4 = 255.75 -> code 256
  EXPECT_NEAR(reported_fit(run.output, "green").gamma, kGamma, 5e-5) << run.output;
  // Green level 1 (code 256) as drawn, read back as float: the centred 20 x 10 patch holds
  // 256 / 1023 within half a code, the surround is black.
  const ImageRGBA green = read_exr(dir.file("patches/006_green_level01.exr")).image;
  EXPECT_NEAR(green.pixel(20, 10)[1] * 1023.0, 256.0, 0.5);
  EXPECT_EQ(green.pixel(20, 10)[0], 0.0f);
  EXPECT_EQ(green.pixel(2, 2)[1], 0.0f);
  EXPECT_EQ(green.pixel(37, 17)[1], 0.0f);
  EXPECT_NEAR(green.pixel(10, 5)[1] * 1023.0, 256.0, 0.5);  // the patch's top-left pixel (x 10..29, y 5..14)
  EXPECT_EQ(green.pixel(9, 5)[1], 0.0f);
}

struct BadReadings {
  std::string name;
  std::string readings;  // with 2 levels: red 0, red 1, green 0, green 1, blue 0, blue 1, white 0, white 1
  std::vector<std::string> messages;  // each in the error
};

class CalibrateBadReadings : public ::testing::TestWithParam<BadReadings> {};

TEST_P(CalibrateBadReadings, AreRefusedWithExit2AndNothingWritten) {
  const test::ScratchDir dir;
  const std::string table = dir.file("out/display.csv");
  const auto run = test::run_glarelab({"calibrate", "--display", "offscreen", "--levels", "2", "--measurements",
                                       dir.write("r.txt", GetParam().readings), "--out", table, "--save-patches",
                                       dir.file("patches")},
                                      dir.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  for (const std::string& message : GetParam().messages) EXPECT_THAT(run.output, ::testing::HasSubstr(message));
  EXPECT_FALSE(std::filesystem::exists(table));
  EXPECT_FALSE(std::filesystem::exists(dir.file("patches"))) << "refused before any patch was shown";
}

INSTANTIATE_TEST_SUITE_P(
    Readings, CalibrateBadReadings,
    ::testing::Values(
        BadReadings{"TooFew", "0.2 50\n0.2 180\n0.2 18\n",
                    {"key 'measurements': expected 8 luminances (2 levels x 4 patches: red, green, blue, white, in "
                     "that order), found 6"}},
        BadReadings{"TooMany", "0.2 50\n0.2 180\n0.2 18\n0.2 250\n251\n", {"found 9"}},
        BadReadings{"Negative", "0.2 50\n0.2 180\n-0.2 18\n0.2 250\n",
                    {"r.txt:3:1: key 'measurements': blue level 1 of 2 (code 0 of 255) (", "negative luminance -0.2 cd/m2"}},
        BadReadings{"Falling", "0.2 50\n0.2 180\n0.2 18\n0.2 0.1\n",
                    {"r.txt:4:5: key 'measurements': white level 2 of 2 (code 255 of 255) (",
                     "0.1 cd/m2 is less than the 0.2 cd/m2 of the level below"}},
        BadReadings{"Flat", "0.2 50\n0.2 0.2\n0.2 18\n0.2 250\n",
                    {"green (", "full drive (0.2 cd/m2) is not brighter than black (0.2 cd/m2)"}},
        BadReadings{"NotANumber", "0.2 50\n0.2 bright\n",
                    {"r.txt:2:5: key 'measurements': expected a luminance in cd/m2, found 'bright'"}}),
    [](const ::testing::TestParamInfo<BadReadings>& param_info) { return param_info.param.name; });

TEST(CalibrateCommand, OffscreenWithoutMeasurementsAndBadLevelsAreRefusedBeforeAnythingIsShown) {
  const test::ScratchDir dir;
  const auto no_readings =
      test::run_glarelab({"calibrate", "--display", "offscreen", "--out", dir.file("t.csv")}, dir.path());
  EXPECT_EQ(no_readings.exit_code, 2);
  EXPECT_THAT(no_readings.output, ::testing::HasSubstr("has nobody reading a photometer at it: give --measurements FILE"));
  const auto too_many = test::run_glarelab({"calibrate", "--display", "offscreen", "--levels", "257", "--measurements",
                                            dir.write("r.txt", "1\n"), "--out", dir.file("t.csv")},
                                           dir.path());
  EXPECT_EQ(too_many.exit_code, 2);
  EXPECT_THAT(too_many.output, ::testing::HasSubstr("--levels must be from 2 (black and full drive) to 256 at 8 bits"));
  const auto wrong_extension =
      test::run_glarelab({"calibrate", "--display", "offscreen", "--out", dir.file("t.txt")}, dir.path());
  EXPECT_EQ(wrong_extension.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir.file("t.csv")));
}

}  // namespace
}  // namespace glarelab
