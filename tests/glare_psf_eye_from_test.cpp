// `glarelab psf` writes the human eye's kernel as a session's frames take it, the lenticular halo
// included when the pupil uncovers the lens-fibre gratings (docs/GLARE_OPTICS.md 9.8), and `psf`
// and `eye-trace` take the eye model from an experiment file's [glare.eye] (--eye-from): a key
// changes what they write, a bad value exits 2 at file:line:column with nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_process.h"

namespace glarelab {
namespace {

// CIE 146:2002's glare spread function per steradian (theta in degrees), written out.
double cie146_gsf(double theta_deg, double age_years, double pigmentation) {
  const double age_factor = 1.0 + std::pow(age_years / 62.5, 4.0);
  return 10.0 / std::pow(theta_deg, 3.0) + (5.0 / (theta_deg * theta_deg) + 0.1 * pigmentation / theta_deg) * age_factor +
         0.0025 * pigmentation;
}

std::vector<std::pair<double, double>> read_profile(const std::string& path) {
  std::istringstream lines(test::read_bytes(path));
  std::string line;
  std::getline(lines, line);
  std::vector<std::pair<double, double>> points;
  while (std::getline(lines, line))
    points.emplace_back(std::stod(line.substr(0, line.find(','))), std::stod(line.substr(line.find(',') + 1)));
  return points;
}

// The profile's largest ratio to the GSF between 2.4 and 3.6 degrees, over its ratio nearest 2 degrees
// (the image is normalised within itself, which scales every angle alike).
double halo_excess(const std::vector<std::pair<double, double>>& profile) {
  double at_two = 0.0, nearest = 1e300, best = 0.0;
  for (const auto& [angle, density] : profile) {
    const double ratio = density / cie146_gsf(angle, 25.0, 0.5);
    if (std::abs(angle - 2.0) < nearest) nearest = std::abs(angle - 2.0), at_two = ratio;
    if (angle > 2.4 && angle < 3.6) best = std::max(best, ratio);
  }
  return best / at_two;
}

std::string pupil_of(const std::string& output) {
  const auto at = output.find(": pupil ");
  return at == std::string::npos ? std::string() : output.substr(at + 8, output.find(' ', at + 8) - at - 8);
}

// The default eye at 100 cd/m2 has a 2.55 mm pupil: the gratings stay covered and the profile has
// no ring. [glare.eye] pupil_min_diameter_mm = 6 holds the pupil at 6 mm, which uncovers them: the
// profile at 2.4-3.6 degrees rises above CIE 146's by the ring (a session's frame shows 2.4x).
TEST(PsfEyeFrom, HumanEyeShowsTheHaloWhenTheFilesPupilUncoversTheGratings) {
  test::ScratchDir dir;
  const std::string eye = dir.write("eye.toml", "[glare.eye]\npupil_min_diameter_mm = 6.0\n");
  const auto run = [&](const std::vector<std::string>& extra, const std::string& name) {
    std::vector<std::string> arguments = {"psf", "--grid", "512", "--degrees-per-pixel", "0.025", "--profile-csv",
                                          (dir.path() / name).string()};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return test::run_glarelab(arguments, dir.path());
  };
  const auto plain = run({}, "plain.csv");
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  const auto held = run({"--eye-from", eye}, "held.csv");
  ASSERT_EQ(held.exit_code, 0) << held.output;
  EXPECT_NE(held.output.find("[glare.eye] of " + eye), std::string::npos) << held.output;
  EXPECT_GE(std::stod(pupil_of(held.output)), 5.99) << held.output;
  EXPECT_LT(std::stod(pupil_of(plain.output)), 3.0) << plain.output;
  EXPECT_NE(plain.output.find("lenticular halo: 0 %"), std::string::npos) << plain.output;
  const double plain_excess = halo_excess(read_profile((dir.path() / "plain.csv").string()));
  const double held_excess = halo_excess(read_profile((dir.path() / "held.csv").string()));
  std::printf("profile / GSF at 2.4-3.6 deg over that at 2 deg: 2.55 mm pupil %.3f, 6 mm pupil %.3f\n", plain_excess,
              held_excess);
  EXPECT_LT(plain_excess, 1.1);
  EXPECT_GT(held_excess, 1.5);
}

TEST(PsfEyeFrom, BadGlareEyeExitsTwoAtItsLineAndColumnWritingNothing) {
  test::ScratchDir dir;
  const auto out = dir.path() / "psf.exr";
  const auto trace = dir.path() / "trace.csv";
  for (const auto& [text, key] :
       std::vector<std::pair<std::string, std::string>>{{"[glare.eye]\n\npupil_min_diameter_mm = 0.1\n", "pupil_min_diameter_mm"},
                                                        {"[glare.eye]\n\npupil_minimum_mm = 2.0\n", "pupil_minimum_mm"},
                                                        {"[glare.eye]\n\nhippus_noise_amplitude = \"x\"\n", "hippus_noise_amplitude"}}) {
    const std::string eye = dir.write("bad.toml", text);
    const auto psf = test::run_glarelab({"psf", "--eye-from", eye, "--grid", "256", "--out", out.string()}, dir.path());
    EXPECT_EQ(psf.exit_code, 2) << psf.output;
    EXPECT_NE(psf.output.find("bad.toml:3:"), std::string::npos) << psf.output;
    EXPECT_NE(psf.output.find("glare.eye." + key), std::string::npos) << psf.output;
    EXPECT_FALSE(std::filesystem::exists(out));
    const auto eye_trace = test::run_glarelab({"eye-trace", "--eye-from", eye, "--out", trace.string()}, dir.path());
    EXPECT_EQ(eye_trace.exit_code, 2) << eye_trace.output;
    EXPECT_NE(eye_trace.output.find("bad.toml:3:"), std::string::npos) << eye_trace.output;
    EXPECT_FALSE(std::filesystem::exists(trace));
  }
  // No [glare.eye] at all, and --eye-from where no eye model is used.
  const std::string empty = dir.write("empty.toml", "[glare]\nmodel = \"cie\"\n");
  const auto none = test::run_glarelab({"psf", "--eye-from", empty, "--out", out.string()}, dir.path());
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_NE(none.output.find("no [glare.eye]"), std::string::npos) << none.output;
  const auto analytic =
      test::run_glarelab({"psf", "--model", "cie", "--eye-from", empty, "--out", out.string()}, dir.path());
  EXPECT_EQ(analytic.exit_code, 2) << analytic.output;
  EXPECT_NE(analytic.output.find("--eye-from"), std::string::npos) << analytic.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// eye-trace: the file's pupil bound holds every sample's pupil at or above it, which the default
// eye at 100 cd/m2 (2.55 mm) is not; a --squint given replaces the file's squint_closure.
TEST(PsfEyeFrom, EyeTraceTakesTheFilesEye) {
  test::ScratchDir dir;
  const std::string eye = dir.write("eye.toml", "[glare.eye]\npupil_min_diameter_mm = 5.0\nsquint_closure = 0.3\n");
  const auto column = [&](const std::vector<std::string>& extra, const std::string& name, const std::string& header) {
    const auto out = dir.path() / name;
    std::vector<std::string> arguments = {"eye-trace", "--duration-s", "2", "--rate-hz", "10", "--out", out.string()};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const auto run = test::run_glarelab(arguments, dir.path());
    EXPECT_EQ(run.exit_code, 0) << run.output;
    std::istringstream lines(test::read_bytes(out.string()));
    std::string line;
    std::getline(lines, line);
    std::size_t index = 0;
    {
      std::istringstream names(line);
      std::string column_name;
      while (std::getline(names, column_name, ',') && column_name != header) ++index;
    }
    std::vector<double> values;
    while (std::getline(lines, line)) {
      std::istringstream cells(line);
      std::string cell;
      for (std::size_t k = 0; k <= index; ++k) std::getline(cells, cell, ',');
      values.push_back(std::stod(cell));
    }
    return values;
  };
  const std::vector<double> plain = column({}, "plain.csv", "pupil_diameter_mm");
  const std::vector<double> held = column({"--eye-from", eye}, "held.csv", "pupil_diameter_mm");
  ASSERT_EQ(plain.size(), 21u);
  ASSERT_EQ(held.size(), 21u);
  for (std::size_t k = 0; k < held.size(); ++k) {
    EXPECT_LT(plain[k], 4.0) << k;
    EXPECT_GE(held[k], 5.0) << k;
  }
  EXPECT_GE(column({"--eye-from", eye}, "squint.csv", "lid_closure").front(), 0.3);
  EXPECT_LT(column({"--eye-from", eye, "--squint", "0"}, "open.csv", "lid_closure").front(), 0.3);
}

}  // namespace
}  // namespace glarelab
