// `glarelab psf` end to end: writes an EXR that reads back with its degreesPerPixel and unit sums.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "cli_process.h"
#include "glare/eye/aperture_components.h"
#include "glare/eye/eye_model.h"
#include "glare/wave/psf_exr.h"
#include "glare_psf_test_support.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

TEST(GlarePsfCommand, WritesMonochromaticPsfExr) {
  test::ScratchDir dir;
  const auto out = (dir.path() / "mono.exr").string();
  const auto run = test::run_glarelab({"psf", "--model", "ritschel", "--pupil-diameter-mm", "3", "--wavelength-nm", "550", "--grid", "256",
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
  const auto run = test::run_glarelab({"psf", "--model", "ritschel", "--spectral", "--wavelength-samples", "8", "--grid", "128",
                                       "--aperture-width-mm", "8", "--gratings", "--out", out},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Psf psf = read_psf_exr(out);
  EXPECT_EQ(psf.channels, 3);
  EXPECT_NEAR(psf.degrees_per_pixel, 575e-9 / 8e-3 * 180.0 / std::numbers::pi, 1e-9);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::channel_sum(psf, c), 1.0, 1e-5) << "channel " << c;

  const auto bad = test::run_glarelab({"psf", "--model", "ritschel", "--backend", "cuda", "--out", out}, dir.path());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  const auto odd = test::run_glarelab({"psf", "--model", "ritschel", "--grid", "255", "--out", out}, dir.path());
  EXPECT_EQ(odd.exit_code, 2) << odd.output;
  EXPECT_NE(odd.output.find("even"), std::string::npos) << odd.output;
  const auto aliased = test::run_glarelab(
      {"psf", "--model", "ritschel", "--fresnel", "paper", "--grid", "64", "--out", (dir.path() / "paper.exr").string()}, dir.path());
  EXPECT_EQ(aliased.exit_code, 0) << aliased.output;
  EXPECT_NE(aliased.output.find("aliased"), std::string::npos) << aliased.output;
}

double relative_l2(const Psf& test, const Psf& reference) {
  double difference = 0.0, norm = 0.0;
  for (std::size_t k = 0; k < reference.values.size(); ++k) {
    difference += (test.values[k] - reference.values[k]) * (test.values[k] - reference.values[k]);
    norm += reference.values[k] * reference.values[k];
  }
  return std::sqrt(difference / norm);
}

TEST(GlarePsfCommand, EyeModelTimeSeedModeComponentsAndBackends) {
  test::ScratchDir dir;
  const auto path = [&](const std::string& name) { return (dir.path() / name).string(); };
  const std::vector<std::string> eye = {"psf", "--model", "ritschel", "--mode", "dynamic", "--time-s", "1.5", "--seed", "7", "--grid", "256",
                                        "--spectral", "--wavelength-samples", "8"};
  const auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> arguments = eye;
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return arguments;
  };
  const auto cpu = test::run_glarelab(with({"--backend", "cpu", "--out", path("cpu.exr")}), dir.path());
  ASSERT_EQ(cpu.exit_code, 0) << cpu.output;
  EXPECT_NE(cpu.output.find("eye model dynamic"), std::string::npos) << cpu.output;
  const auto gl = test::run_glarelab(with({"--backend", "gl", "--out", path("gl.exr")}), dir.path());
  ASSERT_EQ(gl.exit_code, 0) << gl.output;
  const Psf cpu_psf = read_psf_exr(path("cpu.exr")), gl_psf = read_psf_exr(path("gl.exr"));
  ASSERT_EQ(cpu_psf.channels, 3);
  EXPECT_NEAR(cpu_psf.degrees_per_pixel, 575e-9 / 10e-3 * 180.0 / std::numbers::pi, 1e-9);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(test::channel_sum(cpu_psf, c), 1.0, 1e-5) << "channel " << c;
    EXPECT_NEAR(test::channel_sum(gl_psf, c), 1.0, 1e-5) << "channel " << c;
  }
  EXPECT_LE(relative_l2(gl_psf, cpu_psf), 1e-3);
  const auto auto_run = test::run_glarelab(with({"--backend", "auto", "--out", path("auto.exr")}), dir.path());
  ASSERT_EQ(auto_run.exit_code, 0) << auto_run.output;
  EXPECT_NE(auto_run.output.find("auto picked"), std::string::npos) << auto_run.output;

  // Another time moves the eye: a different PSF. The same seed and time: the same file content.
  ASSERT_EQ(test::run_glarelab({"psf", "--model", "ritschel", "--mode", "dynamic", "--time-s", "4", "--seed", "7", "--grid", "256", "--spectral",
                                "--wavelength-samples", "8", "--out", path("later.exr")},
                               dir.path()).exit_code, 0);
  EXPECT_NE(read_psf_exr(path("later.exr")).values, cpu_psf.values);
  ASSERT_EQ(test::run_glarelab(with({"--out", path("again.exr")}), dir.path()).exit_code, 0);
  EXPECT_EQ(read_psf_exr(path("again.exr")).values, cpu_psf.values);

  // The pupil alone, with the pupil and focus given, is the bare-pupil PSF of the classic options.
  ASSERT_EQ(test::run_glarelab({"psf", "--model", "ritschel", "--mode", "dynamic", "--components", "pupil", "--pupil-diameter-mm", "3",
                                "--defocus-dioptres", "0", "--grid", "128", "--out", path("pupil_only.exr")},
                               dir.path()).exit_code, 0);
  ASSERT_EQ(test::run_glarelab({"psf", "--model", "ritschel", "--pupil-diameter-mm", "3", "--grid", "128", "--out", path("bare.exr")},
                               dir.path()).exit_code, 0);
  EXPECT_EQ(read_psf_exr(path("pupil_only.exr")).values, read_psf_exr(path("bare.exr")).values);

  // Control: a delta PSF (convolution with it is the identity).
  ASSERT_EQ(test::run_glarelab({"psf", "--model", "ritschel", "--mode", "control", "--grid", "64", "--out", path("control.exr")}, dir.path())
                .exit_code, 0);
  const Psf control = read_psf_exr(path("control.exr"));
  EXPECT_EQ(control.at(0, 32, 32), 1.0);
  EXPECT_NEAR(test::channel_sum(control, 0), 1.0, 0.0);

  EXPECT_EQ(test::run_glarelab({"psf", "--model", "ritschel", "--mode", "dynamic", "--components", "lens", "--out", path("x.exr")}, dir.path())
                .exit_code, 2);
  EXPECT_EQ(test::run_glarelab({"psf", "--model", "ritschel", "--mode", "dynamic", "--components", "pupil,nose", "--out", path("x.exr")},
                               dir.path()).exit_code, 2);
  EXPECT_EQ(test::run_glarelab({"psf", "--model", "ritschel", "--seed", "3", "--out", path("x.exr")}, dir.path()).exit_code, 2);
}

TEST(GlareApertureComponents, KeepsOnlyTheChosenParts) {
  EyeParameters parameters;
  const ApertureGeometry all = EyeModel(parameters, 11).geometry_at(2.0);
  const ApertureGeometry lens = keep_components(all, parse_component_selection("pupil,lens"));
  std::size_t lens_discs = 0;
  for (const ApertureDisc& disc : all.discs) lens_discs += disc.component == ApertureComponent::lens;
  EXPECT_EQ(static_cast<int>(lens_discs), parameters.lens_particle_count);
  ASSERT_EQ(lens.discs.size(), lens_discs);
  for (const ApertureDisc& disc : lens.discs) EXPECT_EQ(disc.component, ApertureComponent::lens);
  EXPECT_TRUE(lens.lines.empty());
  EXPECT_TRUE(lens.polygons.empty());
  EXPECT_EQ(lens.pupil_diameter_mm, all.pupil_diameter_mm);
  const ApertureGeometry lashes = keep_components(all, parse_component_selection("pupil,lashes"));
  EXPECT_TRUE(lashes.discs.empty());
  EXPECT_EQ(lashes.polygons.size(), all.polygons.size());  // the lids come with the lashes
  const ApertureGeometry every = keep_components(all, parse_component_selection("all"));
  EXPECT_EQ(every.discs.size(), all.discs.size());
  EXPECT_EQ(every.lines.size(), all.lines.size());
  EXPECT_THROW(parse_component_selection("lens"), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab
