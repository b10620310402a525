// `glarelab psf` end to end: writes an EXR that reads back with its degreesPerPixel and unit sums.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cli_process.h"
#include "glare/psf_exr.h"
#include "glare_psf_test_support.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

TEST(GlarePsfCommand, WritesMonochromaticPsfExr) {
  test::ScratchDir dir;
  const auto out = (dir.path() / "mono.exr").string();
  const auto run = test::run_glarelab({"psf", "--pupil-diameter-mm", "3", "--wavelength-nm", "550", "--grid", "256",
                                       "--aperture-width-mm", "12", "--fresnel", "none", "--out", out},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Psf psf = read_psf_exr(out);
  EXPECT_EQ(psf.size_px, 256);
  EXPECT_EQ(psf.channels, 1);
  // lambda / width = 550 nm / 12 mm rad, stored as a float attribute.
  EXPECT_NEAR(psf.degrees_per_pixel, 550e-9 / 12e-3 * 180.0 / std::numbers::pi, 1e-9);
  EXPECT_NEAR(test::channel_sum(psf, 0), 1.0, 1e-5);  // float pixels
}

TEST(GlarePsfCommand, WritesSpectralPsfExrAndRefusesBadOptions) {
  test::ScratchDir dir;
  const auto out = (dir.path() / "spectral.exr").string();
  const auto run = test::run_glarelab({"psf", "--spectral", "--wavelength-samples", "8", "--grid", "128",
                                       "--aperture-width-mm", "8", "--gratings", "--out", out},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Psf psf = read_psf_exr(out);
  EXPECT_EQ(psf.channels, 3);
  EXPECT_NEAR(psf.degrees_per_pixel, 575e-9 / 8e-3 * 180.0 / std::numbers::pi, 1e-9);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::channel_sum(psf, c), 1.0, 1e-5) << "channel " << c;

  const auto bad = test::run_glarelab({"psf", "--backend", "gl", "--out", out}, dir.path());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  const auto odd = test::run_glarelab({"psf", "--grid", "255", "--out", out}, dir.path());
  EXPECT_EQ(odd.exit_code, 2) << odd.output;
  EXPECT_NE(odd.output.find("even"), std::string::npos) << odd.output;
  const auto aliased = test::run_glarelab(
      {"psf", "--fresnel", "paper", "--grid", "64", "--out", (dir.path() / "paper.exr").string()}, dir.path());
  EXPECT_EQ(aliased.exit_code, 0) << aliased.output;
  EXPECT_NE(aliased.output.find("aliased"), std::string::npos) << aliased.output;
}

}  // namespace
}  // namespace glarelab
