// The pieces of `glarelab calibrate` against independent references: the gamma fit against SciPy's
// linregress on the same points (filtered in Python by the stated 1 % rule) and against a
// hand-worked case; the plan's codes and half-float drives against hand-worked values.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "runner/calibration/calibration_plan.h"
#include "runner/calibration/gamma_fit.h"
#include "scipy_support.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

TEST(CalibrateGammaFit, NoisyReadingsGiveSciPysLinregressSlopeOnTheLevelsAboveOnePercent) {
  std::string why;
  if (!test::scipy_available(why)) FAIL() << why;
  // Gamma 2.4 over a 0.5 cd/m2 black to 120 cd/m2, 33 levels, each reading off by up to 3 % in a
  // fixed pattern (a photometer's error without drawing random numbers).
  std::vector<double> drive, luminance;
  std::string csv = "drive,luminance\n";
  for (int i = 0; i <= 32; ++i) {
    const double d = i / 32.0;
    const double reading = 0.5 + 119.5 * std::pow(d, 2.4) * (1.0 + 0.03 * std::sin(7.0 * i));
    drive.push_back(d);
    luminance.push_back(reading);
    char row[96];
    std::snprintf(row, sizeof row, "%.17g,%.17g\n", d, reading);
    csv += row;
  }
  const GammaFit fit = fit_gamma(drive, luminance);
  ASSERT_TRUE(fit.gamma.has_value());
  const test::ScratchDir dir;
  const std::string script = dir.write("fit.py", R"py(
import csv, sys, math
from scipy.stats import linregress
rows = list(csv.DictReader(open(sys.argv[1])))
d = [float(r["drive"]) for r in rows]
L = [float(r["luminance"]) for r in rows]
black, full = L[0], L[-1] - L[0]
x = [math.log10(a) for a, b in zip(d, L) if a > 0 and b - black >= 0.01 * full]
y = [math.log10(b - black) for a, b in zip(d, L) if a > 0 and b - black >= 0.01 * full]
r = linregress(x, y)
rms = math.sqrt(sum((yi - r.intercept - r.slope * xi) ** 2 for xi, yi in zip(x, y)) / len(x))
print("%.17g %d %.17g" % (r.slope, len(x), rms))
)py");
  const std::string output = test::run_python(script, dir.write("readings.csv", csv));
  double slope = 0.0, rms = 0.0;
  int points = 0;
  ASSERT_EQ(std::sscanf(output.c_str(), "%lf %d %lf", &slope, &points, &rms), 3) << output;
  EXPECT_EQ(fit.points, points);
  EXPECT_NEAR(*fit.gamma, slope, 1e-12);
  EXPECT_NEAR(fit.rms_residual_log10, rms, 1e-12);
  EXPECT_NEAR(*fit.gamma, 2.4, 0.05) << "the noise moves the slope a little";
  EXPECT_EQ(fit.black_cd_m2, 0.5);
  EXPECT_EQ(fit.peak_cd_m2, luminance.back());
}

TEST(CalibrateGammaFit, LevelsBelowOnePercentOfTheGainAreLeftOutAndOnePointFitsNothing) {
  // Black 1, gain 100 d^2: drive 0.05 adds 0.25 cd/m2, under 1 % of the full gain, and is left
  // out; 0.5 and 1 give log10(25 / 100) / log10(0.5) = 2 exactly.
  const GammaFit fit = fit_gamma({0.0, 0.05, 0.5, 1.0}, {1.0, 1.25, 26.0, 101.0});
  ASSERT_TRUE(fit.gamma.has_value());
  EXPECT_EQ(fit.points, 2);
  EXPECT_NEAR(*fit.gamma, 2.0, 1e-14);
  EXPECT_NEAR(fit.rms_residual_log10, 0.0, 1e-14);
  const GammaFit two_levels = fit_gamma({0.0, 1.0}, {0.3, 80.0});
  EXPECT_FALSE(two_levels.gamma.has_value());
  EXPECT_EQ(two_levels.points, 1);
  EXPECT_EQ(two_levels.peak_cd_m2, 80.0);
}

TEST(CalibratePlan, CodesAndHalfFloatDrivesAgainstHandWorkedValues) {
  // 5 levels at 8 bits: 255 i / 4 = 0, 63.75, 127.5, 191.25, 255 -> nearest codes (half away from 0).
  const CalibrationPlan eight = make_calibration_plan(5, 8);
  ASSERT_EQ(eight.patches.size(), 20u);
  std::vector<int> codes;
  for (int level = 0; level < 5; ++level) codes.push_back(eight.patch(PatchChannel::green, level).code);
  EXPECT_THAT(codes, ::testing::ElementsAre(0, 64, 128, 191, 255));
  EXPECT_DOUBLE_EQ(eight.patch(PatchChannel::blue, 1).drive, 64.0 / 255.0);
  EXPECT_EQ(eight.patches[5].channel, PatchChannel::green);  // red's 5 levels first
  const std::array<double, 3> white = eight.patch(PatchChannel::white, 2).rgb_drive();
  EXPECT_EQ(white[0], 128.0 / 255.0);
  EXPECT_EQ(white[2], 128.0 / 255.0);
  EXPECT_EQ(eight.describe(eight.patch(PatchChannel::red, 4)), "red level 5 of 5 (code 255 of 255)");
  // Every code once at 256 levels; 10 bits up to 1024.
  const CalibrationPlan all = make_calibration_plan(256, 8);
  for (int level = 0; level < 256; ++level) EXPECT_EQ(all.patch(PatchChannel::red, level).code, level);
  EXPECT_EQ(make_calibration_plan(1024, 10).patch(PatchChannel::red, 1023).code, 1023);
  // Half float: i / 3 rounded to 11 significant bits: 1/3 = 0x1.555...p-2 -> 0x1.554p-2 =
  // 0.333251953125, 2/3 -> 0x1.554p-1 = 0.66650390625.
  const CalibrationPlan half = make_calibration_plan(4, 16);
  EXPECT_EQ(half.patch(PatchChannel::red, 1).code, -1);
  EXPECT_EQ(half.patch(PatchChannel::red, 1).drive, 0.333251953125);
  EXPECT_EQ(half.patch(PatchChannel::red, 2).drive, 0.66650390625);
  EXPECT_EQ(half.patch(PatchChannel::red, 3).drive, 1.0);
  EXPECT_EQ(half.describe(half.patch(PatchChannel::red, 1)), "red level 2 of 4 (drive 0.333252)");
  EXPECT_THROW(make_calibration_plan(257, 8), std::invalid_argument);
  EXPECT_THROW(make_calibration_plan(1, 8), std::invalid_argument);
  EXPECT_THROW(make_calibration_plan(17, 12), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab
