// The observer's refraction through the command line: a residual the [glare] grid cannot sample is
// refused by `glarelab run` (exit 2, nothing written) and by `glarelab validate` with the same
// message, naming the condition, the residual and the grid needed; `glarelab render` shows the very
// frame the session shows for a condition with spectacles.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/exr_io.h"
#include "runner/store/result_store.h"
#include "cli_process.h"

namespace glarelab {
namespace {

using test::run_glarelab;
using test::ScratchDir;

// The example, its scene path made absolute so that a copy elsewhere still finds it.
std::string example_text() {
  std::string text = test::read_bytes(std::string(GLARELAB_SOURCE_DIR) + "/examples/presbyope_reading_glasses.toml");
  const std::string relative = "file = \"scenes/";
  if (const auto at = text.find(relative); at != std::string::npos)
    text.replace(at, relative.size(), "file = \"" + std::string(GLARELAB_SOURCE_DIR) + "/examples/scenes/");
  return text;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The example's uncorrected residual, -2 D (60 years: 0.5 D of amplitude against 2.5 D at 0.4 m),
// at the eye's largest pupil (9 mm): a grid of 256 px over 10 mm samples at most
// 575 nm / (2 x 4.5 mm x 0.039 mm) = 1.64 D at 575 nm, so the file is refused; it needs
// 2 x 4.5 mm x 2 D x 10 mm / 575 nm = 313 px there, and 319 px at 624 nm, where the eye's LCA
// makes the error 2.21 D (the finest grid any wavelength needs is the one named).
TEST(RefractionSessionCli, UnsampledResidualIsRefusedBeforeAnythingIsWritten) {
  const ScratchDir scratch;
  const auto file = scratch.path() / "coarse.toml";
  test::write_bytes(file.string(), replaced(example_text(), "grid_px = 512", "grid_px = 256"));
  const auto db = scratch.path() / "never.db";
  const auto run = run_glarelab({"run", file.string(), "--display", "offscreen", "--observer", "simulated", "--db",
                                 db.string()},
                                scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  for (const std::string part : {"glare.grid_px", "condition 'without_glasses'", "spectacles 'none'",
                                 "-2 / 0 x 0 D", "grid_px of at least 319", "grid_px 256 samples at most",
                                 "largest pupil (9 mm"})
    EXPECT_NE(run.output.find(part), std::string::npos) << part << " in: " << run.output;
  EXPECT_EQ(run.output.find("with_reading_glasses"), std::string::npos) << "the corrected condition is sampled";
  EXPECT_FALSE(std::filesystem::exists(db));
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "results"));

  const auto validate = run_glarelab({"validate", file.string()}, scratch.path());
  EXPECT_EQ(validate.exit_code, 2) << validate.output;
  EXPECT_NE(validate.output.find("glare.grid_px"), std::string::npos) << validate.output;
  EXPECT_NE(validate.output.find("condition 'without_glasses'"), std::string::npos) << validate.output;
}

// An analytic model has no pupil to carry a refraction: refused rather than shown unblurred.
TEST(RefractionSessionCli, AnalyticModelWithARefractionIsRefused) {
  const ScratchDir scratch;
  const auto file = scratch.path() / "spencer.toml";
  test::write_bytes(file.string(), replaced(example_text(), "model = \"ritschel\"", "model = \"spencer\""));
  const auto validate = run_glarelab({"validate", file.string()}, scratch.path());
  EXPECT_EQ(validate.exit_code, 2) << validate.output;
  EXPECT_NE(validate.output.find("has no pupil to carry it"), std::string::npos) << validate.output;
}

// `glarelab render` runs the seeded session up to the condition's first frame: the frame it writes
// is the session's own first frame of that condition (--save-frames), bit for bit, with the
// spectacles and the residual named in its description.
TEST(RefractionSessionCli, RenderShowsTheSessionsFrameWithSpectacles) {
  const ScratchDir scratch;
  const std::string example = std::string(GLARELAB_SOURCE_DIR) + "/examples/presbyope_reading_glasses.toml";
  const auto validate = run_glarelab({"validate", example}, scratch.path());
  ASSERT_EQ(validate.exit_code, 0) << validate.output;
  EXPECT_NE(validate.output.find("condition 'without_glasses': spectacles 'none'"), std::string::npos) << validate.output;
  EXPECT_NE(validate.output.find("residual sphere -2 D"), std::string::npos) << validate.output;
  EXPECT_NE(validate.output.find("condition 'with_reading_glasses': spectacles 'reading' (2.5 / 0 x 0 at 12 mm)"),
            std::string::npos)
      << validate.output;

  const auto frames = scratch.path() / "frames";
  const auto db = scratch.path() / "study.db";
  const auto run = run_glarelab({"run", example, "--display", "offscreen", "--observer", "simulated", "--db",
                                 db.string(), "--save-frames", frames.string()},
                                scratch.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const ResultStore store(db.string());
  const auto trials = store.load_trials(store.load_sessions().at(0).id);
  for (const std::string condition : {"with_reading_glasses", "without_glasses"}) {
    int first = -1;
    for (const TrialRecord& trial : trials)
      if (first < 0 && trial.condition.find("\"name\":\"" + condition + "\"") != std::string::npos) first = trial.trial_index;
    ASSERT_GE(first, 0) << condition;
    const auto out = scratch.path() / (condition + ".exr");
    const auto render = run_glarelab({"render", example, "--condition", condition, "--out", out.string()}, scratch.path());
    ASSERT_EQ(render.exit_code, 0) << render.output;
    EXPECT_NE(render.output.find(condition == "without_glasses" ? "spectacles none (residual -2 / 0 x 0 D)"
                                                                : "spectacles reading (residual 0 / 0 x 0 D)"),
              std::string::npos)
        << render.output;
    char name[32];
    std::snprintf(name, sizeof name, "trial_%04d.exr", first);
    const ImageRGBA session_frame = read_exr((frames / name).string()).image;
    const ImageRGBA rendered = read_exr(out.string()).image;
    EXPECT_EQ(session_frame.rgba, rendered.rgba) << condition << ": render differs from the session's trial " << first;
  }
}

}  // namespace
}  // namespace glarelab
