// `glarelab psf --model spencer|cie|hybrid|ritschel` run as a user would: the profile CSV against
// the papers' formulas written out here (Spencer 1995 Eq. 5/8 with Eq. 10, CIE 146:2002), the Airy
// pattern and a second azimuthal average of the written image; the images' unit sums, angular
// scale and pixel ratios against the density times the pixel's solid angle; the refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cli_process.h"
#include "glare/wave/psf_exr.h"
#include "glare/wave/psf_scale.h"
#include "glare_psf_test_support.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

constexpr double kRad = std::numbers::pi / 180.0;

struct Row {
  double angle_deg;
  double per_sr;
};

std::vector<Row> read_profile(const std::filesystem::path& path, std::string* header = nullptr) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  if (header) *header = line;
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    Row row{};
    char comma = 0;
    fields >> row.angle_deg >> comma >> row.per_sr;
    rows.push_back(row);
  }
  return rows;
}

// Spencer et al. 1995, Eq. 5 and 8 with Eq. 10's age term (6.9e-9 A^4 from f0 to f2), the halo at
// 568 nm with Hemenger's exponent 19.75 (Eq. 6).
double spencer_per_sr(double theta, double w0, double w1, double w2, double w3, double age_years) {
  const double shift = 6.9e-9 * std::pow(age_years, 4);
  const double f0 = 2.61e6 * std::exp(-std::pow(theta / 0.02, 2));
  const double f1 = 20.91 / std::pow(theta + 0.02, 3);
  const double f2 = 72.37 / std::pow(theta + 0.02, 2);
  const double f3 = 436.9 * std::exp(-19.75 * std::pow(theta - 3.0, 2));
  return (w0 - shift) * f0 + w1 * f1 + (w2 + shift) * f2 + w3 * f3;
}

// CIE 146:2002's general glare spread function.
double cie_per_sr(double theta, double age_years, double p) {
  return 10.0 / std::pow(theta, 3) + (5.0 / (theta * theta) + 0.1 * p / theta) * (1.0 + std::pow(age_years / 62.5, 4)) +
         0.0025 * p;
}

void expect_profile_angles(const std::vector<Row>& rows) {
  ASSERT_GE(rows.size(), 2u);
  EXPECT_EQ(rows.front().angle_deg, 0.01);
  EXPECT_EQ(rows.back().angle_deg, 90.0);
  // Log-spaced (equal ratios) and at least 20 per decade (each ratio at most 10^(1/20)).
  const double ratio = rows[1].angle_deg / rows[0].angle_deg;
  EXPECT_LE(ratio, std::pow(10.0, 1.0 / 20.0));
  for (std::size_t i = 1; i < rows.size(); ++i)
    EXPECT_NEAR(rows[i].angle_deg / rows[i - 1].angle_deg, ratio, 1e-12) << rows[i].angle_deg;
  EXPECT_GE(static_cast<double>(rows.size() - 1), 20.0 * std::log10(9000.0));
}

TEST(GlarePsfModelsCommand, SpencerProfileIsEquationEightWithTheAgeTerm) {
  test::ScratchDir dir;
  const auto csv = dir.path() / "spencer.csv";
  const auto run = test::run_glarelab({"psf", "--model", "spencer", "--regime", "mesopic", "--age-years", "60", "--grid",
                                       "32", "--profile-csv", csv.string(), "--out", (dir.path() / "s.exr").string()},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::string header;
  const std::vector<Row> rows = read_profile(csv, &header);
  EXPECT_EQ(header, "angle_deg,psf_per_sr");
  expect_profile_angles(rows);
  for (const Row& row : rows)
    EXPECT_NEAR(row.per_sr, spencer_per_sr(row.angle_deg, 0.368, 0.478, 0.138, 0.016, 60.0),
                1e-12 * spencer_per_sr(row.angle_deg, 0.368, 0.478, 0.138, 0.016, 60.0))
        << row.angle_deg;

  // The default regime is photopic (Eq. 5) and the default age 25.
  const auto photopic_csv = dir.path() / "photopic.csv";
  ASSERT_EQ(test::run_glarelab({"psf", "--model", "spencer", "--grid", "32", "--profile-csv", photopic_csv.string(),
                                "--out", (dir.path() / "p.exr").string()},
                               dir.path()).exit_code, 0);
  for (const Row& row : read_profile(photopic_csv))
    EXPECT_NEAR(row.per_sr, spencer_per_sr(row.angle_deg, 0.384, 0.478, 0.138, 0.0, 25.0),
                1e-12 * spencer_per_sr(row.angle_deg, 0.384, 0.478, 0.138, 0.0, 25.0))
        << row.angle_deg;
}

TEST(GlarePsfModelsCommand, CieProfileIsTheGlareSpreadFunction) {
  test::ScratchDir dir;
  const auto csv = dir.path() / "cie.csv";
  const auto run = test::run_glarelab({"psf", "--model", "cie", "--age-years", "70", "--pigmentation", "0.2", "--grid",
                                       "32", "--profile-csv", csv.string(), "--out", (dir.path() / "c.exr").string()},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<Row> rows = read_profile(csv);
  expect_profile_angles(rows);
  for (const Row& row : rows)
    EXPECT_NEAR(row.per_sr, cie_per_sr(row.angle_deg, 70.0, 0.2), 1e-12 * cie_per_sr(row.angle_deg, 70.0, 0.2))
        << row.angle_deg;
}

TEST(GlarePsfModelsCommand, ProfileAloneNeedsNoImageAndNothingToWriteIsRefused) {
  test::ScratchDir dir;
  const auto csv = dir.path() / "only.csv";
  const auto run = test::run_glarelab({"psf", "--model", "cie", "--profile-csv", csv.string()}, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<Row> rows = read_profile(csv);
  expect_profile_angles(rows);
  EXPECT_NEAR(rows.front().per_sr, cie_per_sr(0.01, 25.0, 0.5), 1e-12 * cie_per_sr(0.01, 25.0, 0.5));
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    EXPECT_NE(entry.path().extension(), ".exr") << entry.path();  // no image was asked for
  const auto nothing = test::run_glarelab({"psf", "--model", "spencer"}, dir.path());
  EXPECT_EQ(nothing.exit_code, 2) << nothing.output;
  EXPECT_NE(nothing.output.find("--profile-csv"), std::string::npos) << nothing.output;
}

// The image: unit sum, its angle per pixel, and pixels in the ratio of P(theta) dOmega, with theta
// = atan(r tan(dpp)) and dOmega = tan^2(dpp) / (1 + r^2 tan^2(dpp))^(3/2) on the flat display.
TEST(GlarePsfModelsCommand, AnalyticImagesAreTheDensityOverThePixelsSolidAngles) {
  test::ScratchDir dir;
  const double dpp = 0.05, t = std::tan(dpp * kRad);
  const auto density_times_solid_angle = [&](double r, auto&& per_sr) {
    return per_sr(std::atan(r * t) / kRad) * t * t / std::pow(1.0 + r * r * t * t, 1.5);
  };
  struct Case {
    std::vector<std::string> arguments;
    std::function<double(double)> per_sr;
  };
  const std::vector<Case> cases = {
      {{"--model", "spencer", "--age-years", "40"},
       [](double theta) { return spencer_per_sr(theta, 0.384, 0.478, 0.138, 0.0, 40.0); }},
      {{"--model", "cie", "--pigmentation", "0.9"}, [](double theta) { return cie_per_sr(theta, 25.0, 0.9); }}};
  for (const Case& c : cases) {
    const auto out = (dir.path() / "image.exr").string();
    std::vector<std::string> arguments = {"psf", "--grid", "160", "--degrees-per-pixel", "0.05", "--out", out};
    arguments.insert(arguments.end(), c.arguments.begin(), c.arguments.end());
    const auto run = test::run_glarelab(arguments, dir.path());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const Psf psf = read_psf_exr(out);
    EXPECT_EQ(psf.size_px, 160);
    EXPECT_EQ(psf.channels, 1);
    EXPECT_NEAR(psf.degrees_per_pixel, dpp, 1e-8);
    EXPECT_NEAR(test::channel_sum(psf, 0), 1.0, 1e-5);
    // Far from the core a pixel's energy is its centre's density times its solid angle to
    // (1/24) |f''/f| per axis, under 1e-3 at 40-70 pixels.
    const double reference = density_times_solid_angle(40.0, c.per_sr);
    const double at_40 = psf.at(0, 80 + 40, 80);
    for (const auto& [dx, dy] : {std::pair{0, 55}, std::pair{-42, 42}, std::pair{70, 0}, std::pair{-30, -60}}) {
      const double r = std::hypot(dx, dy);
      EXPECT_NEAR(psf.at(0, 80 + dx, 80 + dy) / at_40, density_times_solid_angle(r, c.per_sr) / reference,
                  2e-3 * density_times_solid_angle(r, c.per_sr) / reference)
          << c.arguments[1] << " at " << dx << ", " << dy;
    }
  }
}

TEST(GlarePsfModelsCommand, RitschelProfileIsTheImagesAzimuthalMeanPerSteradian) {
  test::ScratchDir dir;
  const auto csv = dir.path() / "airy.csv";
  const auto out = (dir.path() / "airy.exr").string();
  // A 3 mm pupil at 550 nm over 24 mm: 0.0013 degrees per pixel, the Airy core 19 px wide.
  const auto run = test::run_glarelab({"psf", "--model", "ritschel", "--pupil-diameter-mm", "3", "--wavelength-nm", "550", "--grid", "1024",
                                       "--aperture-width-mm", "24", "--fresnel", "none", "--supersampling", "4",
                                       "--profile-csv", csv.string(), "--out", out},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Psf psf = read_psf_exr(out);
  const std::vector<Row> rows = read_profile(csv);
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.front().angle_deg, 0.01);
  // Only angles the grid reaches: half the grid less one pixel.
  const double reach = (512.0 - 1.0) * psf.degrees_per_pixel;
  EXPECT_LE(rows.back().angle_deg, reach);
  EXPECT_GT(rows.back().angle_deg * std::pow(10.0, 1.0 / 20.0), reach);
  // A second azimuthal average (the test support's 1-pixel rings) per steradian, read linearly.
  const std::vector<double> rings = test::radial_profile(psf, 0);
  const double pixel_sr = std::pow(psf.degrees_per_pixel * kRad, 2);
  for (const Row& row : rows) {
    const double r = row.angle_deg / psf.degrees_per_pixel;
    const auto k = static_cast<std::size_t>(r);
    const double f = r - std::floor(r);
    const double expected = ((1.0 - f) * rings[k] + f * rings[k + 1]) / pixel_sr;
    EXPECT_NEAR(row.per_sr, expected, 1e-5 * expected + 1e-3) << row.angle_deg;
  }
  // The Airy pattern per steradian, (pi D^2 / 4 lambda^2) (2 J1(x) / x)^2, x = pi D sin(theta) / lambda
  // (the FFT samples it at the pixels' centres), averaged on the same rings and read at 0.01 degrees
  // (7.6 px, x = 2.99, on the core's flank).
  const double d_m = 3e-3, lambda_m = 550e-9;
  const auto airy = [&](double theta_deg) {
    const double x = std::numbers::pi * d_m * std::sin(theta_deg * kRad) / lambda_m;
    const double shape = x == 0.0 ? 1.0 : 2.0 * std::cyl_bessel_j(1.0, x) / x;
    return std::numbers::pi * d_m * d_m / (4.0 * lambda_m * lambda_m) * shape * shape;
  };
  const auto airy_ring = [&](int k) {
    double sum = 0.0, count = 0.0;
    for (int dy = -k - 1; dy <= k + 1; ++dy)
      for (int dx = -k - 1; dx <= k + 1; ++dx)
        if (std::lround(std::hypot(dx, dy)) == k) {
          sum += airy(std::hypot(dx, dy) * psf.degrees_per_pixel);
          count += 1.0;
        }
    return sum / count;
  };
  const double r = 0.01 / psf.degrees_per_pixel;
  const int k = static_cast<int>(std::floor(r));
  const double expected = (1.0 - (r - k)) * airy_ring(k) + (r - k) * airy_ring(k + 1);
  EXPECT_NEAR(rows.front().per_sr, expected, 0.02 * expected);
}

TEST(GlarePsfModelsCommand, HybridIsTheWaveEyeNearAndTheAnalyticFarField) {
  test::ScratchDir dir;
  const auto csv = dir.path() / "hybrid.csv";
  const auto out = (dir.path() / "hybrid.exr").string();
  // 575 nm over 8 mm: 0.00412 deg/px; the reach 127 x 0.00412 x 380/575 = 0.346 deg; the default
  // hand-over 0.156-0.311 deg; the image 256 px of 0.02 deg.
  const auto run = test::run_glarelab({"psf", "--model", "hybrid", "--mode", "dynamic", "--seed", "3", "--grid", "256",
                                       "--aperture-width-mm", "8", "--spectral", "--wavelength-samples", "8",
                                       "--degrees-per-pixel", "0.02", "--age-years", "50", "--profile-csv", csv.string(),
                                       "--out", out},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Psf psf = read_psf_exr(out);
  EXPECT_EQ(psf.size_px, 256);
  EXPECT_EQ(psf.channels, 3);
  EXPECT_NEAR(psf.degrees_per_pixel, 0.02, 1e-8);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::channel_sum(psf, c), 1.0, 1e-5) << c;
  // Beyond the hand-over the image is Spencer's photopic kernel (over the image's sum): the profile
  // follows Eq. 5 with the age term in shape; ratios to its value at 1 degree.
  const std::vector<Row> rows = read_profile(csv);
  const auto spencer = [](double theta) { return spencer_per_sr(theta, 0.384, 0.478, 0.138, 0.0, 50.0); };
  const Row* at_one = nullptr;
  for (const Row& row : rows)
    if (std::abs(row.angle_deg - 1.0) < 0.06) at_one = &row;
  ASSERT_NE(at_one, nullptr);
  int checked = 0;
  for (const Row& row : rows) {
    if (row.angle_deg < 0.6) continue;  // 30 px and more: ring and interpolation errors under 2e-3
    const double expected = spencer(row.angle_deg) / spencer(at_one->angle_deg);
    EXPECT_NEAR(row.per_sr / at_one->per_sr, expected, 5e-3 * expected) << row.angle_deg;
    ++checked;
  }
  EXPECT_GE(checked, 10);
  // Inside the inner radius (0.156 deg: 7.8 px) the image is the scaled wave-optics PSF: the same
  // eye written by --model ritschel, mapped to 0.02 degree pixels here, in one ratio everywhere.
  const auto wave_out = (dir.path() / "wave.exr").string();
  ASSERT_EQ(test::run_glarelab({"psf", "--model", "ritschel", "--mode", "dynamic", "--seed", "3", "--grid", "256", "--aperture-width-mm", "8",
                                "--spectral", "--wavelength-samples", "8", "--out", wave_out},
                               dir.path()).exit_code, 0);
  const Psf wave = resample_psf_to_display(read_psf_exr(wave_out), 0.02);
  int inside = 0;
  for (int c = 0; c < 3; ++c) {
    const double ratio = psf.at(c, 128, 128) / wave.at(c, wave.size_px / 2, wave.size_px / 2);
    for (int dy = -7; dy <= 7; ++dy)
      for (int dx = -7; dx <= 7; ++dx) {
        if (std::hypot(dx, dy) > 7.0) continue;
        const double wave_value = wave.at(c, wave.size_px / 2 + dx, wave.size_px / 2 + dy);
        EXPECT_NEAR(psf.at(c, 128 + dx, 128 + dy), ratio * wave_value, 1e-5 * ratio * wave_value + 1e-12)
            << "channel " << c << " at " << dx << ", " << dy;
        ++inside;
      }
  }
  EXPECT_EQ(inside, 3 * 149);
  // The image reaches half its side less one pixel: 127 x 0.02 = 2.54 degrees.
  EXPECT_LE(rows.back().angle_deg, std::atan(127.0 * std::tan(0.02 * kRad)) / kRad);
  EXPECT_EQ(rows.front().angle_deg, 0.01);
}

TEST(GlarePsfModelsCommand, RefusesBadModelOptionsNamingTheFlagAndWritesNothing) {
  test::ScratchDir dir;
  const auto out = dir.path() / "refused.exr";
  const auto csv = dir.path() / "refused.csv";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--model", "spencer", "--age-years", "0"}, "--age-years"},
      {{"--model", "spencer", "--age-years", "101"}, "--age-years"},
      {{"--model", "cie", "--age-years", "nan"}, "--age-years"},
      {{"--model", "cie", "--pigmentation", "1.5"}, "--pigmentation"},
      {{"--model", "cie", "--pigmentation", "-0.1"}, "--pigmentation"},
      {{"--model", "vos"}, "--model"},
      {{"--model", "spencer", "--regime", "adaptive"}, "--regime"},
      {{"--model", "spencer", "--regime", "dusk"}, "--regime"},
      {{"--model", "spencer", "--pigmentation", "0.3"}, "--pigmentation"},
      {{"--model", "cie", "--regime", "scotopic"}, "--regime"},
      {{"--model", "cie", "--pupil-diameter-mm", "3"}, "--pupil-diameter-mm"},
      {{"--model", "ritschel", "--age-years", "30"}, "--age-years"},
      {{"--model", "hybrid", "--grid", "256", "--handover-deg", "0.1,0.6"}, "--handover-deg"},
      {{"--model", "hybrid", "--grid", "256", "--handover-deg", "0.3,0.2"}, "--handover-deg"},
      {{"--model", "hybrid", "--grid", "256", "--handover-deg", "0.1"}, "--handover-deg"},
      {{"--model", "hybrid", "--grid", "256", "--degrees-per-pixel", "0.001"}, "--degrees-per-pixel"},
      {{"--model", "spencer", "--handover-deg", "0.1,0.2"}, "--handover-deg"},
  };
  for (const auto& [extra, flag] : cases) {
    std::vector<std::string> arguments = {"psf", "--profile-csv", csv.string(), "--out", out.string()};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const auto run = test::run_glarelab(arguments, dir.path());
    EXPECT_EQ(run.exit_code, 2) << extra[extra.size() - 1] << ": " << run.output;
    EXPECT_NE(run.output.find(flag), std::string::npos) << run.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << run.output;
    EXPECT_FALSE(std::filesystem::exists(csv)) << run.output;
  }
  // The hand-over beyond the reach names both angles and the reach (0.1 and 0.6 against 127 x 575 nm
  // / 10 mm = 0.4184 deg for a one-wavelength PSF of 256 px over 10 mm; 127 x 380 nm / 10 mm =
  // 0.2765 deg with --spectral, whose 380 nm copy leaves the grid first).
  const auto beyond = test::run_glarelab(
      {"psf", "--model", "hybrid", "--grid", "256", "--handover-deg", "0.1,0.6", "--out", out.string()}, dir.path());
  EXPECT_NE(beyond.output.find("0.1 deg"), std::string::npos) << beyond.output;
  EXPECT_NE(beyond.output.find("0.6 deg"), std::string::npos) << beyond.output;
  EXPECT_NE(beyond.output.find("0.4184 deg"), std::string::npos) << beyond.output;
  const auto spectral = test::run_glarelab(
      {"psf", "--model", "hybrid", "--spectral", "--grid", "256", "--handover-deg", "0.1,0.3", "--out", out.string()},
      dir.path());
  EXPECT_EQ(spectral.exit_code, 2) << spectral.output;
  EXPECT_NE(spectral.output.find("0.2765 deg"), std::string::npos) << spectral.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace glarelab
