// `glarelab psf`, `render` and `eye-trace` refuse what they cannot honour, as a user meets it: NaN and
// infinite numbers, a defocus no grid can sample, a pupil the grid cannot hold or whose PSF it cannot
// hold, output names whose extension the file would not match. Each refusal exits 2, names the flag
// and writes nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "glare/wave/fresnel.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

void expect_refused(const test::RunOutput& run, const std::vector<std::string>& words, const std::filesystem::path& out) {
  EXPECT_EQ(run.exit_code, 2) << run.output;
  for (const std::string& word : words) EXPECT_NE(run.output.find(word), std::string::npos) << word << "\n" << run.output;
  EXPECT_FALSE(std::filesystem::exists(out)) << out;
}

TEST(CliBadNumbers, PsfRefusesNanAndInfinityForEveryFloatingOption) {
  test::ScratchDir dir;
  const auto out = dir.path() / "psf.exr";
  const std::vector<std::vector<std::string>> cases = {
      {"--defocus-dioptres", "nan"},  {"--defocus-dioptres", "-inf"}, {"--pupil-diameter-mm", "nan"},
      {"--wavelength-nm", "nan"},     {"--wavelength-nm", "inf"},     {"--aperture-width-mm", "nan"},
      {"--aperture-width-mm", "inf"}, {"--time-s", "nan"}};
  for (const auto& option : cases) {
    std::vector<std::string> arguments = {"psf", "--model", "ritschel", "--grid", "64", "--out", out.string()};
    if (option[0] == "--time-s") arguments.insert(arguments.end(), {"--mode", "dynamic"});
    arguments.insert(arguments.end(), option.begin(), option.end());
    expect_refused(test::run_glarelab(arguments, dir.path()), {option[0], "finite"}, out);
  }
}

TEST(CliBadNumbers, PsfRefusesADefocusNoGridCanSampleNamingTheLargestItCan) {
  test::ScratchDir dir;
  const auto out = dir.path() / "psf.exr";
  const auto run = test::run_glarelab({"psf", "--model", "ritschel", "--defocus-dioptres", "1e30", "--out", out.string()}, dir.path());
  // Defaults: 4 mm pupil, 10 mm over 512 px, 575 nm. lambda / (2 r dx): 8192 px -> 117.8 D, 512 px -> 7.36 D.
  expect_refused(run, {"--defocus-dioptres", "1e+30 D needs a grid of", "the largest grid, 8192, samples at most 117.8 D",
                       "--grid 512 at most 7.36 D"},
                 out);
  EXPECT_EQ(run.output.find("-9223372036854775808"), std::string::npos) << run.output;
  // Past what 512 px sample but within 8192: computed, with the aliasing warning (as before).
  const auto aliased = test::run_glarelab({"psf", "--model", "ritschel", "--defocus-dioptres", "20", "--grid", "64", "--out", out.string()},
                                          dir.path());
  EXPECT_EQ(aliased.exit_code, 0) << aliased.output;
  EXPECT_NE(aliased.output.find("aliased"), std::string::npos) << aliased.output;
}

TEST(CliBadNumbers, PhaseSamplingReportDoesNotOverflowForHugeDefocus) {
  const PhaseSamplingReport report =
      check_phase_sampling(phase_coefficient_per_m2(PhaseForm::defocus, 575.0, 1e30), 2.0, 10.0 / 512, 10.0);
  EXPECT_TRUE(report.aliased);
  EXPECT_GT(report.required_grid_px_exact, 1e31);  // 10 mm / (1 / (2 c r)), c = 1e30 D / 575 nm
  EXPECT_EQ(report.required_grid_px, std::numeric_limits<long long>::max());
  EXPECT_EQ(report.warning.find("-9223372036854775808"), std::string::npos) << report.warning;
  EXPECT_NE(report.warning.find("e+31 px"), std::string::npos) << report.warning;
  EXPECT_NEAR(max_sampled_defocus_dioptres(575.0, 2.0, 10.0 / 512), 575e-9 / (2 * 2e-3 * 10e-3 / 512), 1e-9);
}

TEST(CliBadNumbers, PsfRefusesAPupilTheGridCannotHoldOrSample) {
  test::ScratchDir dir;
  const auto out = dir.path() / "psf.exr";
  // Pupil wider than the grid: the grid would clip it and give a point PSF.
  expect_refused(test::run_glarelab({"psf", "--model", "ritschel", "--pupil-diameter-mm", "4", "--aperture-width-mm", "1", "--out", out.string()},
                                    dir.path()),
                 {"--aperture-width-mm", "wider than the aperture grid", "at least 8"}, out);
  // Pupil spanning 0.002 px: its Airy core is 610,000 px wide, far wider than the 512 px grid.
  expect_refused(
      test::run_glarelab({"psf", "--model", "ritschel", "--pupil-diameter-mm", "4", "--aperture-width-mm", "1e6", "--out", out.string()}, dir.path()),
      {"--aperture-width-mm", "Airy disc", "wider than the grid", "at most 839.3"}, out);
  // The same through the eye model's pupil (1.5-9 mm): a grid 0.01 mm wide holds none of it.
  expect_refused(test::run_glarelab({"psf", "--model", "ritschel", "--mode", "static", "--aperture-width-mm", "0.01", "--out", out.string()},
                                    dir.path()),
                 {"--aperture-width-mm", "the eye model at --time-s"}, out);
  // A core wider than a quarter of the grid is computed, with a warning saying why it is poor.
  const auto crowded = test::run_glarelab({"psf", "--model", "ritschel", "--grid", "16", "--out", out.string()}, dir.path());
  EXPECT_EQ(crowded.exit_code, 0) << crowded.output;
  EXPECT_NE(crowded.output.find("more than a quarter of the 16 px grid"), std::string::npos) << crowded.output;
}

TEST(CliBadNumbers, PsfOfAClosedEyeIsRefused) {
  test::ScratchDir dir;
  const auto out = dir.path() / "psf.exr";
  // Seed 1 blinks with the lids fully closed at 0.94 s (`glarelab eye-trace --seed 1`): no light, no PSF.
  expect_refused(test::run_glarelab({"psf", "--model", "ritschel", "--mode", "dynamic", "--seed", "1", "--time-s", "0.94", "--grid", "64", "--out",
                                     out.string()},
                                    dir.path()),
                 {"--time-s", "no light passes the aperture"}, out);
}

TEST(CliBadNumbers, PsfWritesOnlyExr) {
  test::ScratchDir dir;
  for (const std::string name : {"psf.png", "psf.tiff", "psf"}) {
    const auto out = dir.path() / name;
    expect_refused(test::run_glarelab({"psf", "--model", "ritschel", "--grid", "64", "--out", out.string()}, dir.path()), {"--out", "must end in .exr"},
                   out);
  }
  const auto upper = dir.path() / "PSF.EXR";
  EXPECT_EQ(test::run_glarelab({"psf", "--model", "ritschel", "--grid", "64", "--out", upper.string()}, dir.path()).exit_code, 0);
  EXPECT_TRUE(std::filesystem::exists(upper));
}

TEST(CliBadNumbers, EyeTraceRefusesNanInfinityAndOutOfRangeNumbers) {
  test::ScratchDir dir;
  const auto out = dir.path() / "trace.csv";
  const std::vector<std::vector<std::string>> cases = {
      {"--duration-s", "nan", "finite"},          {"--duration-s", "-1", ">= 0"},
      {"--rate-hz", "nan", "finite"},             {"--rate-hz", "inf", "finite"},
      {"--rate-hz", "0", "> 0"},                  {"--field-luminance-cd-m2", "inf", "finite"},
      {"--field-luminance-cd-m2", "-5", "> 0"},   {"--static-time-s", "nan", "finite"},
      {"--squint", "nan", "finite"},              {"--squint", "2", "from 0 to 1"}};
  for (const auto& option : cases)
    expect_refused(test::run_glarelab({"eye-trace", "--duration-s", "1", option[0], option[1], "--out", out.string()},
                                      dir.path()),
                   {option[0], option[2]}, out);
}

TEST(CliBadNumbers, RenderRefusesOtherExtensionsBeforeRendering) {
  test::ScratchDir dir;
  ImageRGBA scene(16, 16, 1.0f);
  write_exr((dir.path() / "flat.exr").string(), scene);
  const std::string experiment = dir.write("experiment.toml", R"([experiment]
name = "render-out"
seed = 1

[display]
width_px = 64
height_px = 32

[scenes]
flat = { file = "flat.exr" }

[procedure]
type = "forced_choice"
stimulus_frames = 2

[[conditions.rows]]
name = "plain"
scene_a = "flat"
scene_b = "flat"
glare = "control"
)");
  for (const std::string name : {"frame.tiff", "frame.jpg", "frame"}) {
    const auto out = dir.path() / name;
    expect_refused(test::run_glarelab({"render", experiment, "--condition", "plain", "--out", out.string()}, dir.path()),
                   {"--out", "must end in .exr or .png"}, out);
  }
  const auto out = dir.path() / "frame.exr";
  expect_refused(
      test::run_glarelab({"render", experiment, "--condition", "plain", "--time", "inf", "--out", out.string()}, dir.path()),
      {"--time", "finite"}, out);
  EXPECT_EQ(test::run_glarelab({"render", experiment, "--condition", "plain", "--out", out.string()}, dir.path()).exit_code,
            0);
}

}  // namespace
}  // namespace glarelab
