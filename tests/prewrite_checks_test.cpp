// Input that can only be judged with the scenes, display and glare together is still refused
// before the session row exists: exit 2, the reason, and no database file.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "cli_process.h"
#include "core/exr_io.h"

namespace glarelab {
namespace {

test::RunOutput run_variant(const test::ScratchDir& scratch,
                            const std::vector<std::pair<std::string, std::string>>& replacements) {
  const auto experiment = test::demo_variant(scratch.path(), replacements);
  return test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated", "--db",
                             (scratch.path() / "never.db").string()},
                            scratch.path());
}

TEST(PrewriteChecks, GlareADisplayCannotShowIsRefusedBeforeTheSessionExists) {
  const test::ScratchDir scratch;
  // 100 mm pixels seen from 10 mm: one pixel spans 157 deg, the 0.84 deg PSF less than a pixel.
  const auto run = run_variant(scratch, {{"viewing_distance_mm", "viewing_distance_mm = 10.0"},
                                         {"pixel_pitch_mm", "pixel_pitch_mm = 100.0"}});
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("key 'glare': the glare cannot be shown on this [display]: glare/wave/psf_scale: the PSF spans"),
            std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "never.db"));
}

// --save-frames into a path that is a file: refused (exit 2, the path given is wrong) before the
// session exists; into a directory it writes every trial's first stimulus frame.
TEST(PrewriteChecks, SaveFramesIntoAFileIsRefusedAndIntoADirectoryWritesEveryTrial) {
  const test::ScratchDir scratch;
  const auto experiment = test::demo_variant(scratch.path(), {});
  const auto blocked = scratch.path() / "a_file";
  test::write_bytes(blocked.string(), "not a directory");
  const auto refused = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer",
                                           "simulated", "--db", (scratch.path() / "never.db").string(),
                                           "--save-frames", blocked.string()},
                                          scratch.path());
  // A path the user gave that cannot be a folder: an input error (2), not the store's (4).
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("a_file"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("is a file, not a directory"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "never.db"));

  const auto frames = scratch.path() / "frames";
  const auto saved = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer",
                                         "simulated", "--db", (scratch.path() / "saved.db").string(), "--stop-after",
                                         "2", "--save-frames", frames.string()},
                                        scratch.path());
  EXPECT_EQ(saved.exit_code, 0) << saved.output;
  EXPECT_TRUE(std::filesystem::exists(frames / "trial_0000.exr"));
  EXPECT_TRUE(std::filesystem::exists(frames / "trial_0001.exr"));
  EXPECT_FALSE(std::filesystem::exists(frames / "trial_0002.exr"));
  EXPECT_FALSE(std::filesystem::exists(frames / ".glarelab_write_check"));
}

// --display egl where EGL cannot start (glvnd pointed at no vendor library): exit 3 naming what
// EGL answered, before the session exists; --display offscreen runs on OSMesa and logs why.
TEST(PrewriteChecks, EglThatCannotStartExitsThreeAndOffscreenFallsBackSayingWhy) {
  const test::ScratchDir scratch;
  ASSERT_EQ(setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/glarelab_no_vendor.json", 1), 0);
  const std::string demo = std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml";
  const auto refused = test::run_glarelab({"run", demo, "--display", "egl", "--observer", "simulated", "--db",
                                           (scratch.path() / "never.db").string()},
                                          scratch.path());
  EXPECT_EQ(refused.exit_code, 3) << refused.output;
  EXPECT_NE(refused.output.find("EGL: no display could be opened: "), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "never.db"));

  const auto fallback = test::run_glarelab({"run", demo, "--display", "offscreen", "--observer", "simulated", "--db",
                                            (scratch.path() / "osmesa.db").string(), "--stop-after", "1"},
                                           scratch.path());
  unsetenv("__EGL_VENDOR_LIBRARY_FILENAMES");
  EXPECT_EQ(fallback.exit_code, 0) << fallback.output;
  EXPECT_NE(fallback.output.find("via OSMesa (EGL did not start: EGL: no display could be opened"), std::string::npos)
      << fallback.output;
}

// Without a [presentation] table the default text (0.6 deg) must fit the display too: the stored
// configuration writes the default out and must read back (the experiment_file fuzz replay found
// a display 16 px high that loaded but whose stored configuration did not).
TEST(PrewriteChecks, DefaultTextTallerThanTheDisplayIsRefusedSayingItIsTheDefault) {
  const test::ScratchDir scratch;
  const auto experiment = test::demo_variant(scratch.path(), {{"height_px", "height_px = 16"}});
  const auto run = test::run_glarelab({"validate", experiment.string()}, scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  // 16 px of 0.25 mm at 600 mm: 2 atan(2 / 600) = 0.38197 deg.
  EXPECT_NE(run.output.find("key 'presentation.text_height_deg': must fit the display: at most 0.38197 deg (its "
                            "height at viewing_distance_mm), found 0.6 (the default; set it in [presentation])"),
            std::string::npos)
      << run.output;
}

TEST(PrewriteChecks, TextTallerThanTheDisplayIsRefusedAtItsKey) {
  const test::ScratchDir scratch;
  const auto experiment = test::demo_variant(scratch.path(), {});
  test::write_bytes(experiment.string(), test::read_bytes(experiment) + "\n[presentation]\ntext_height_deg = 1000\n");
  const auto run = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                       "--db", (scratch.path() / "never.db").string()},
                                      scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  // The demo's display: 512 px of 0.25 mm at 600 mm, 2 atan(64 / 600) = 12.1771 deg high.
  EXPECT_NE(run.output.find("key 'presentation.text_height_deg': must fit the display: at most 12.1771 deg (its "
                            "height at viewing_distance_mm), found 1000"),
            std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "never.db"));
}

TEST(PrewriteChecks, ASceneNoGlTextureCanHoldIsRefused) {
  const test::ScratchDir scratch;
  ImageRGBA wide(16385, 1);
  const auto scene = scratch.path() / "wide.exr";
  write_exr(scene.string(), wide);
  const auto run = run_variant(scratch, {{"lamp_200", "lamp_200 = { file = \"" + scene.string() + "\" }"}});
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find(scene.string() + ": scene 'lamp_200' is 16385 x 1 px; at most 16384 px a side"),
            std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "never.db"));
}

TEST(PrewriteChecks, ScenesBothAboveTheDisplaysPeakAreRefusedWithoutGlare) {
  const test::ScratchDir scratch;
  // The dim lamps (100 to 200 cd/m2 in a dim room) without glare: on a 50 cd/m2 display every lamp
  // is white.
  test::write_demo_conditions_without_glare(scratch.path() / "conditions.csv");
  const auto run = run_variant(scratch, {{"peak_luminance_cd_m2", "peak_luminance_cd_m2 = 50.0"},
                                         {"file", "file = \"" + (scratch.path() / "conditions.csv").string() + "\""}});
  EXPECT_EQ(run.exit_code, 2) << run.output;
  const std::string csv = (scratch.path() / "conditions.csv").string() + ":2:1";
  EXPECT_NE(run.output.find(csv + ": condition 'ratio_1.05': scenes 'lamp_100' (peak "), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("are both above the display's peak_luminance_cd_m2 (50): it shows both at its white"),
            std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "never.db"));
  // The demo's own lamps are all above its 250 cd/m2, and every row gives one side glare: it runs.
  const auto shown = test::run_glarelab({"run", std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml", "--display",
                                         "offscreen", "--observer", "simulated", "--db",
                                         (scratch.path() / "fine.db").string(), "--stop-after", "1"},
                                        scratch.path());
  EXPECT_EQ(shown.exit_code, 0) << shown.output;
}

}  // namespace
}  // namespace glarelab
