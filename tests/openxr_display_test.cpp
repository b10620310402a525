// The OpenXR display (`--display openxr`) against a real runtime, Monado's simulated headset with
// its null compositor (tests/openxr_runtime.h), with the core validation layer on: a whole session
// stores every trial and one frames row per submitted frame, stamped with predicted display times
// one runtime period (50 ms) apart; each view's swapchain image, read back on the client side, is
// its half of the side-by-side frame, and the frames drawn are a side-by-side session's; and
// without a runtime the run exits 3 naming OpenXR and quoting the loader. The OpenXrViews suite makes the display in this process and runs under Xvfb
// (tests/CMakeLists.txt); the others start glarelab under xvfb-run themselves.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "core/image.h"
#include "openxr_runtime.h"
#include "raw_db.h"
#include "runner/display/display_backend.h"
#include "runner/display/openxr_clock.h"
#include "runner/display/openxr_display.h"
#include "runner/session/session_runner.h"
#include "window_focus.h"

namespace glarelab {
namespace {

// The demo's lamps side by side in each eye's half: a stereo display 1024 x 551 (two 512 x 551
// views), two stimulus frames a trial, five rows x two sides = 10 trials. The display model is the
// headset's (docs/STEREO.md, "Degrees in the headset"): Monado's simulated views span 85 deg across,
// 2 atan(tan(42.5 deg) x 0.07 / 0.065) = 89.2 deg high (its display's 65 x 70 mm per eye,
// simulated_hmd.c), so 512 px across make a pixel 600 x 2 tan(42.5 deg) / 512 = 2.1477 mm at
// 600 mm, and 512 x 0.07 / 0.065 = 551 px high keep it square. `more` replaces further lines.
std::filesystem::path stereo_demo(const std::filesystem::path& dir,
                                  const std::vector<std::pair<std::string, std::string>>& more = {}) {
  std::filesystem::create_directories(dir);
  test::write_demo_conditions_without_glare(dir / "conditions.csv");
  std::vector<std::pair<std::string, std::string>> lines = {
      {"file", "file = \"" + (dir / "conditions.csv").string() + "\""},
      {"width_px", "width_px = 1024"},
      {"height_px", "height_px = 551"},
      {"pixel_pitch_mm", "pixel_pitch_mm = 2.1477"},
      {"encoding", "encoding = \"srgb\"\nstereo = \"side_by_side\""},
      {"stimulus_frames", "stimulus_frames = 2"},
      {"question", "question = \"\""},
      {"wavelength_samples", "wavelength_samples = 8"}};
  for (const auto& [key, line] : more) {
    bool replaced = false;
    for (auto& [known, known_line] : lines)
      if (known == key) {
        known_line = line;
        replaced = true;
      }
    if (!replaced) lines.emplace_back(key, line);
  }
  return test::demo_variant(dir, lines);
}

struct ShellRun {
  int exit_code = -1;
  std::string output;
};

ShellRun shell(const std::string& command, const std::filesystem::path& output_file) {
  const int status = std::system((command + " > '" + output_file.string() + "' 2>&1").c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, test::read_bytes(output_file.string())};
}

TEST(OpenXrDisplay, WithoutARuntimeExitsThreeNamingOpenXrAndQuotingTheLoader) {
  const test::ScratchDir scratch;
  const std::filesystem::path experiment = stereo_demo(scratch.path());
  const std::filesystem::path db = scratch.path() / "session.db";
  // A runtime manifest that does not exist: the loader finds no runtime, whatever is installed.
  const ShellRun run = shell("env XR_RUNTIME_JSON='" + (scratch.path() / "no-runtime.json").string() + "' '" +
                                 std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                 "' --display openxr --observer simulated --db '" + db.string() + "'",
                             scratch.path() / "output.txt");
  EXPECT_EQ(run.exit_code, 3) << run.output;
  EXPECT_NE(run.output.find("OpenXR"), std::string::npos) << run.output;
  if (GLARELAB_HAVE_OPENXR) {
    EXPECT_NE(run.output.find("no runtime could be started (xrCreateInstance: XR_ERROR_RUNTIME_UNAVAILABLE)"),
              std::string::npos)
        << run.output;
    // The loader's own words, quoted in the one error line (it names the manifest it could not use).
    EXPECT_NE(run.output.find("the OpenXR loader said: "), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("no-runtime.json"), std::string::npos) << run.output;
  } else {
    EXPECT_NE(run.output.find("built without the OpenXR loader"), std::string::npos) << run.output;
  }
  EXPECT_FALSE(std::filesystem::exists(db)) << "nothing is written before the display opens";
}

// A mono experiment cannot be shown in a headset (each view is a half of a side-by-side frame):
// refused at --display, exit 2, before the display opens or anything is written.
TEST(OpenXrDisplay, MonoExperimentIsRefusedAtTheDisplayOptionBeforeAnythingIsWritten) {
  const test::ScratchDir scratch;
  std::filesystem::create_directories(scratch.path());
  test::write_demo_conditions_without_glare(scratch.path() / "conditions.csv");
  const std::filesystem::path experiment = test::demo_variant(
      scratch.path(), {{"file", "file = \"" + (scratch.path() / "conditions.csv").string() + "\""}});
  const std::filesystem::path db = scratch.path() / "session.db";
  const ShellRun run = shell("'" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                 "' --display openxr --observer simulated --db '" + db.string() + "'",
                             scratch.path() / "output.txt");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--display: key 'display': openxr shows each eye its half of a side-by-side frame: "
                            "the experiment needs [display] stereo = \"side_by_side\""),
            std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("OpenXR:"), std::string::npos) << "refused before the display opens: " << run.output;
  EXPECT_FALSE(std::filesystem::exists(db));
}

// A window-only option is refused likewise: the headset's mirror window is never the participant's screen.
TEST(OpenXrDisplay, AFullScreenIsRefusedAtTheDisplayOptionBeforeAnythingIsWritten) {
  const test::ScratchDir scratch;
  std::filesystem::create_directories(scratch.path());
  test::write_demo_conditions_without_glare(scratch.path() / "conditions.csv");
  const std::filesystem::path experiment =
      test::demo_variant(scratch.path(), {{"file", "file = \"" + (scratch.path() / "conditions.csv").string() + "\""},
                                          {"encoding", "encoding = \"srgb\"\nstereo = \"side_by_side\"\nfullscreen = true"}});
  const std::filesystem::path db = scratch.path() / "session.db";
  const ShellRun run = shell("'" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                 "' --display openxr --observer simulated --db '" + db.string() + "'",
                             scratch.path() / "output.txt");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--display: key 'display': openxr shows the frames in the headset, with a mirror window "
                            "for the keyboard: [display] fullscreen = true is for --display window"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("OpenXR:"), std::string::npos) << "refused before the display opens: " << run.output;
  EXPECT_FALSE(std::filesystem::exists(db));
}

// "FILE:LINE:" of the first line of `file` that starts with `start`: where a refusal points.
std::string line_of(const std::filesystem::path& file, const std::string& start) {
  std::istringstream text(test::read_bytes(file.string()));
  std::string line;
  for (int number = 1; std::getline(text, line); ++number)
    if (line.rfind(start, 0) == 0) return file.string() + ":" + std::to_string(number) + ":";
  return file.string() + ": no line " + start;
}

// A study made for a headset says so in its file ([display] output = "openxr"): without --display
// the run is a headset run, and the file's key is where a refusal points; the flag wins (the same
// file runs offscreen); another value is refused at the key. None of this needs a runtime.
TEST(OpenXrDisplay, TheFilesOutputChoosesTheHeadsetAndTheDisplayFlagWins) {
  const test::ScratchDir scratch;
  std::filesystem::create_directories(scratch.path());
  test::write_demo_conditions_without_glare(scratch.path() / "conditions.csv");
  // Mono: a headset run refuses it, at the file's output key.
  const std::filesystem::path experiment = test::demo_variant(
      scratch.path(), {{"file", "file = \"" + (scratch.path() / "conditions.csv").string() + "\""},
                       {"width_px", "width_px = 1024\noutput = \"openxr\""},
                       {"stimulus_frames", "stimulus_frames = 2"}});
  const std::filesystem::path db = scratch.path() / "session.db";
  const ShellRun from_file = shell("'" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                       "' --observer simulated --db '" + db.string() + "'",
                                   scratch.path() / "output.txt");
  EXPECT_EQ(from_file.exit_code, 2) << from_file.output;
  EXPECT_NE(from_file.output.find(line_of(experiment, "output =") + "10: key 'display.output': openxr shows each eye "
                                  "its half of a side-by-side frame"),
            std::string::npos)
      << from_file.output;
  EXPECT_FALSE(std::filesystem::exists(db));
  // The flag wins: the same file offscreen.
  const ShellRun offscreen = shell("'" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                       "' --display offscreen --observer simulated --stop-after 1 --db '" + db.string() + "'",
                                   scratch.path() / "offscreen.txt");
  EXPECT_EQ(offscreen.exit_code, 0) << offscreen.output;
  const test::RawDb raw(db.string());
  EXPECT_EQ(raw.rows("SELECT count(*) FROM trials")[0][0], "1");
  // The stored configuration keeps the key, so a resumed session is shown where the file meant.
  EXPECT_NE(raw.rows("SELECT config FROM sessions")[0][0].find("output = 'openxr'"), std::string::npos);

  const std::filesystem::path other = test::demo_variant(
      scratch.path(), {{"file", "file = \"" + (scratch.path() / "conditions.csv").string() + "\""},
                       {"width_px", "width_px = 1024\noutput = \"headset\""}});
  const ShellRun refused = shell("'" + std::string(GLARELAB_BINARY) + "' run '" + other.string() +
                                     "' --display offscreen --observer simulated --db '" +
                                     (scratch.path() / "other.db").string() + "'",
                                 scratch.path() / "other.txt");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find(line_of(other, "output =") + "10: key 'display.output': must be \"window\" or "
                                "\"openxr\""),
            std::string::npos)
      << refused.output;
}

// The display model's degrees are the views' (docs/STEREO.md, "Degrees in the headset"): a pitch
// the file states must agree with them. At 100 mm, 512 px across the simulated views' 85 deg make a
// pixel 100 x 2 tan(42.5 deg) / 512 = 0.3579 mm; the file's 1 mm (each lamp would span
// 2 atan(128 / 100) = 104 deg, more than a view) is refused at its key once the runtime has given
// the views, before anything is written.
TEST(OpenXrDisplay, APixelPitchThatContradictsTheViewsIsRefusedAtItsKeyBeforeAnythingIsWritten) {
  if (const auto missing = test::openxr_runtime_missing(true)) GTEST_SKIP() << *missing;
  const test::ScratchDir scratch;
  const std::filesystem::path experiment = stereo_demo(
      scratch.path(), {{"viewing_distance_mm", "viewing_distance_mm = 100.0"}, {"pixel_pitch_mm", "pixel_pitch_mm = 1.0"}});
  const std::filesystem::path db = scratch.path() / "session.db";
  const ShellRun run = shell("xvfb-run -a -s '-screen 0 1280x1024x24 -noreset' env " + test::monado_environment() +
                                 " '" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                 "' --display openxr --observer simulated --db '" + db.string() + "'",
                             scratch.path() / "output.txt");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  char pitch[32];
  std::snprintf(pitch, sizeof pitch, "%.4f", 100.0 * 2.0 * std::tan(42.5 * 3.14159265358979323846 / 180.0) / 512.0);
  EXPECT_NE(run.output.find(line_of(experiment, "pixel_pitch_mm") + "18: key 'display.pixel_pitch_mm': 1 mm contradicts "
                            "the headset's views: 512 x 551 px across the left eye's view's 85.0 x 89.2 deg make a "
                            "pixel " + std::string(pitch) + " mm at viewing_distance_mm 100"),
            std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(db));
}

// A view's pixels must be square: halves of 512 x 256 px would stretch every scene to twice its
// height in the views (89.2 deg over 256 px against 85 deg over 512). Refused at height_px, naming
// the height that makes them square, 512 x 0.07 / 0.065 = 551.4 px.
TEST(OpenXrDisplay, AHeightThatStretchesTheViewsPixelsIsRefusedAtItsKey) {
  if (const auto missing = test::openxr_runtime_missing(true)) GTEST_SKIP() << *missing;
  const test::ScratchDir scratch;
  const std::filesystem::path experiment = stereo_demo(scratch.path(), {{"height_px", "height_px = 256"}});
  const std::filesystem::path db = scratch.path() / "session.db";
  const ShellRun run = shell("xvfb-run -a -s '-screen 0 1280x1024x24 -noreset' env " + test::monado_environment() +
                                 " '" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                 "' --display openxr --observer simulated --db '" + db.string() + "'",
                             scratch.path() / "output.txt");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find(line_of(experiment, "height_px") + "13: key 'display.height_px': the headset's left eye's "
                            "view is 85.0 x 89.2 deg: with halves of 512 x 256 px its pixels are 2.1477 mm across"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("height_px = 551 makes them square"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(db));
}

// A study for a headset need not state a pitch: the views give it, from each view's field of view
// as the runtime locates it (the display event's edges) and the half's 512 px, at the file's 600 mm:
// 600 (tan(right) - tan(left)) / 512. The session is prepared with it (its stored configuration
// says so, so a resumed session keeps it) and the display_model event says where it came from.
TEST(OpenXrDisplay, WithoutAPixelPitchTheViewsGiveItToTheSession) {
  if (const auto missing = test::openxr_runtime_missing(true)) GTEST_SKIP() << *missing;
  const test::ScratchDir scratch;
  const std::filesystem::path experiment = stereo_demo(scratch.path(), {{"pixel_pitch_mm", ""}});
  ASSERT_EQ(test::read_bytes(experiment.string()).find("pixel_pitch_mm"), std::string::npos);
  const std::filesystem::path db = scratch.path() / "session.db";
  const ShellRun run = shell("xvfb-run -a -s '-screen 0 1280x1024x24 -noreset' env " + test::monado_environment() +
                                 " '" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                 "' --display openxr --observer simulated --stop-after 1 --db '" + db.string() + "'",
                             scratch.path() / "output.txt");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const test::RawDb raw(db.string());
  const std::string display = raw.value("SELECT message FROM session_events WHERE kind = 'display'");
  const std::size_t edges = display.find("fields of view (");
  ASSERT_NE(edges, std::string::npos) << display;
  double left_deg = 0.0, right_deg = 0.0, up_deg = 0.0, down_deg = 0.0;
  ASSERT_EQ(std::sscanf(display.c_str() + edges, "fields of view (%lf, %lf, %lf, %lf)", &left_deg, &right_deg, &up_deg,
                        &down_deg),
            4)
      << display;
  const double radians = 3.14159265358979323846 / 180.0;
  const double pitch_mm = 600.0 * (std::tan(right_deg * radians) - std::tan(left_deg * radians)) / 512.0;
  char expected[160];
  std::snprintf(expected, sizeof expected, "pixel_pitch_mm not stated: the session takes %.4f mm", pitch_mm);
  const std::string model = raw.value("SELECT message FROM session_events WHERE kind = 'display_model'");
  EXPECT_NE(model.find(expected), std::string::npos) << model;
  EXPECT_EQ(model.rfind("from the headset's views: 512 x 551 px across the left eye's view's 85.0 x 89.2 deg", 0), 0u)
      << model;
  const std::string config = raw.value("SELECT config FROM sessions");
  const std::size_t stored = config.find("pixel_pitch_mm = ");
  ASSERT_NE(stored, std::string::npos) << config;
  // The edges are printed to 0.01 deg: the pitch from them is that close.
  EXPECT_NEAR(std::stod(config.substr(stored + std::strlen("pixel_pitch_mm = "))), pitch_mm, 2e-4 * pitch_mm) << config;

  // Resumed, the stored configuration states the pitch it took: the views agree with it.
  const ShellRun resumed = shell("xvfb-run -a -s '-screen 0 1280x1024x24 -noreset' env " + test::monado_environment() +
                                     " '" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                     "' --display openxr --observer simulated --stop-after 1 --resume 1 --db '" +
                                     db.string() + "'",
                                 scratch.path() / "resumed.txt");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const test::RawDb after(db.string());
  EXPECT_EQ(after.value("SELECT count(*) FROM trials"), "2");
  const auto models = after.rows("SELECT message FROM session_events WHERE kind = 'display_model' ORDER BY id");
  ASSERT_EQ(models.size(), 2u);
  EXPECT_NE(models[1][0].find("agrees within 1 %"), std::string::npos) << models[1][0];
}

// Sizes in degrees take the views' degrees: Spencer's disc (generated at 4 deg across, inside a
// 6-deg annulus of a third of its luminance) in a headset study without a pitch spans
// 2 d tan(2 deg) / pitch pixels of each eye's half, the pitch being the views'
// (600 (tan(right) - tan(left)) / 512 mm, from the display event's edges): 19.5 px. The first
// stimulus frame (--save-frames, linear cd/m2, no glare) is measured along the disc's middle row,
// each pixel by its share of the way from the annulus to the disc (the edges are antialiased by
// area). At the file's default 0.25 mm the disc would be 168 px across. (The file is read before
// the views are known: its generated scenes must also fit their size_px at the default pitch,
// docs/STEREO.md.)
TEST(OpenXrDisplay, ASceneSizedInDegreesSpansItsDegreesOfTheViews) {
  if (const auto missing = test::openxr_runtime_missing(true)) GTEST_SKIP() << *missing;
  const test::ScratchDir scratch;
  std::filesystem::create_directories(scratch.path());
  test::write_bytes((scratch.path() / "discs.csv").string(), "name,scene_a,scene_b\ndiscs,disc,disc\n");
  const std::filesystem::path experiment = stereo_demo(
      scratch.path(), {{"pixel_pitch_mm", ""},
                       {"file", "file = \"" + (scratch.path() / "discs.csv").string() + "\""},
                       {"bright_3077", "disc = { generator = \"disc_annulus\", size_px = 254, disc_diameter_deg = 4.0, "
                                       "annulus_diameter_deg = 6.0, disc_fraction_of_peak = 1.0 }"}});
  const std::filesystem::path db = scratch.path() / "session.db";
  const ShellRun run = shell("xvfb-run -a -s '-screen 0 1280x1024x24 -noreset' env " + test::monado_environment() +
                                 " '" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                 "' --display openxr --observer simulated --stop-after 1 --db '" + db.string() +
                                 "' --save-frames '" + (scratch.path() / "frames").string() + "'",
                             scratch.path() / "output.txt");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const test::RawDb raw(db.string());
  const std::string display = raw.value("SELECT message FROM session_events WHERE kind = 'display'");
  double left_deg = 0.0, right_deg = 0.0, up_deg = 0.0, down_deg = 0.0;
  const std::size_t edges = display.find("fields of view (");
  ASSERT_NE(edges, std::string::npos) << display;
  ASSERT_EQ(std::sscanf(display.c_str() + edges, "fields of view (%lf, %lf, %lf, %lf)", &left_deg, &right_deg, &up_deg,
                        &down_deg),
            4);
  const double radians = 3.14159265358979323846 / 180.0;
  const double pitch_mm = 600.0 * (std::tan(right_deg * radians) - std::tan(left_deg * radians)) / 512.0;
  const double disc_px = 2.0 * 600.0 * std::tan(2.0 * radians) / pitch_mm;

  const ImageRGBA frame = read_exr((scratch.path() / "frames" / "trial_0000.exr").string()).image;
  ASSERT_EQ(frame.width_px, 1024);
  ASSERT_EQ(frame.height_px, 551);
  // Each eye's half: two columns of 256 px, the disc centred in each; its middle row.
  const int row = 551 / 2;
  for (int eye = 0; eye < 2; ++eye)
    for (int column = 0; column < 2; ++column) {
      const int left_px = eye * 512 + column * 256;
      double disc_cd_m2 = 0.0, annulus_cd_m2 = 1e300;
      for (int x = left_px; x < left_px + 256; ++x) {
        const float* p = frame.pixel(x, row);
        disc_cd_m2 = std::max(disc_cd_m2, luminance_rec709(p[0], p[1], p[2]));
      }
      // The annulus: the middle of the ring between the disc's and the annulus' edges.
      const double ring_px = (disc_px / 2.0 + 2.0 * 600.0 * std::tan(3.0 * radians) / pitch_mm / 2.0) / 2.0;
      const float* ring = frame.pixel(left_px + 128 + static_cast<int>(std::lround(ring_px)), row);
      annulus_cd_m2 = luminance_rec709(ring[0], ring[1], ring[2]);
      ASSERT_NEAR(annulus_cd_m2, disc_cd_m2 / 3.0, 0.02 * disc_cd_m2) << "eye " << eye << " column " << column;
      double covered_px = 0.0;  // the disc's pixels, each by its share of the disc over the annulus
      for (int x = left_px; x < left_px + 256; ++x) {
        const float* p = frame.pixel(x, row);
        const double share = (luminance_rec709(p[0], p[1], p[2]) - annulus_cd_m2) / (disc_cd_m2 - annulus_cd_m2);
        if (share > 0.0) covered_px += std::min(share, 1.0);
      }
      EXPECT_NEAR(covered_px, disc_px, 0.5) << "eye " << eye << " column " << column << ": pitch " << pitch_mm;
    }
}

TEST(OpenXrDisplay, SessionUnderMonadoStoresEveryTrialWithPredictedFlipsOnePeriodApart) {
  if (const auto missing = test::openxr_runtime_missing(true)) GTEST_SKIP() << *missing;
  const test::ScratchDir scratch;
  const std::filesystem::path experiment = stereo_demo(scratch.path());
  const std::filesystem::path db = scratch.path() / "session.db";
  const std::filesystem::path validation = scratch.path() / "validation.txt";
  const ShellRun run = shell("xvfb-run -a -s '-screen 0 1280x1024x24 -noreset' env " + test::monado_environment() +
                                 " XR_CORE_VALIDATION_EXPORT_TYPE=text XR_CORE_VALIDATION_FILE_NAME='" +
                                 validation.string() + "' '" + std::string(GLARELAB_BINARY) + "' run '" +
                                 experiment.string() + "' --display openxr --observer simulated --db '" +
                                 db.string() + "'",
                             scratch.path() / "output.txt");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // The core validation layer was loaded and wrote nothing: it writes each breach of the OpenXR
  // specification ("[VALID_ERROR | VUID-...]") to its file, made at the first one.
  EXPECT_NE(run.output.find("Core Validation output type: text"), std::string::npos) << run.output;
  const std::string validation_text =
      std::filesystem::exists(validation) ? test::read_bytes(validation.string()) : std::string();
  EXPECT_EQ(validation_text, "");
  EXPECT_EQ(run.output.find("VUID"), std::string::npos) << run.output;

  const test::RawDb raw(db.string());
  const auto session = raw.rows("SELECT status, clock FROM sessions");
  ASSERT_EQ(session.size(), 1u);
  EXPECT_EQ(session[0][0], "completed");
  EXPECT_EQ(session[0][1], "predicted");
  EXPECT_EQ(raw.rows("SELECT count(*) FROM trials")[0][0], "10");
  const auto display_event = raw.rows("SELECT message FROM session_events WHERE kind = 'display'");
  ASSERT_EQ(display_event.size(), 1u);
  EXPECT_NE(display_event[0][0].find("system 'Monado: Simulated HMD', 2 views 512x551"), std::string::npos)
      << display_event[0][0];
  // The simulated headset has no eye tracker: the display event says so.
  EXPECT_NE(display_event[0][0].find("eye gaze: none (XR_EXT_eye_gaze_interaction offered, the system has no eye "
                                     "tracker)"),
            std::string::npos)
      << display_event[0][0];
  // The file's pitch agrees with the views' (stereo_demo): the session keeps it, and says so.
  EXPECT_NE(raw.value("SELECT message FROM session_events WHERE kind = 'display_model'")
                .find("the file's pixel_pitch_mm 2.1477 mm agrees within 1 %"),
            std::string::npos);

  // Every flip is a submitted frame's predicted display time: the runtime's period (50 ms with the
  // null compositor) apart, or a whole number of periods where a frame missed its slot (the session
  // did work between frames); never the same frame twice, never a fraction of a period. Within a
  // trial, a step of two periods or more is a dropped frame in the frames table (the 1.5-period rule).
  // The demo's trials flip only their two stimulus frames: 20 submitted frames, 20 rows.
  const auto frames = raw.rows("SELECT trial_id, frame_index, flip_s, dropped FROM frames ORDER BY rowid");
  ASSERT_EQ(frames.size(), 20u);
  const double period_s = 0.050;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const double step_s = std::stod(frames[i][2]) - std::stod(frames[i - 1][2]);
    const double periods = step_s / period_s;
    EXPECT_GE(std::lround(periods), 1) << "flip " << i << " step " << step_s << " s";
    EXPECT_NEAR(periods, std::round(periods), 1e-4) << "flip " << i << " step " << step_s << " s";
    if (frames[i][0] == frames[i - 1][0] && frames[i][1] == "1" && frames[i - 1][1] == "0") {
      EXPECT_EQ(frames[i][3], std::lround(periods) >= 2 ? "1" : "0") << "trial " << frames[i][0] << " step " << step_s;
    }
  }
}

// The Luidolt example in the headset (examples/luidolt_ratings_headset.toml: its real-lamp block
// and its three simulations, [display] output = "openxr"), shortened to one rating category, two
// stimulus frames a trial and half the pixels each way (the same degrees): 4 trials. Offscreen first (the file is valid and complete wherever
// the runtime is missing), then with no --display, so the file's output takes it into Monado's
// headset, with the core validation layer on: no validation message, every trial stored, and one
// frames row per submitted frame (the runtime's frame loop runs only inside present()), each a
// predicted display time whole periods of 50 ms after the one before.
TEST(OpenXrDisplay, LuidoltExampleRunsInTheHeadsetWithEveryTrialAndFrame) {
  const test::ScratchDir scratch;
  std::filesystem::create_directories(scratch.path());
  std::string text = test::read_bytes(std::string(GLARELAB_SOURCE_DIR) + "/examples/luidolt_ratings_headset.toml");
  const auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("stimulus_duration_s = 0.2 ", "stimulus_frames = 2 #");
  replace("categories = [\"glare appearance\", \"glare movement\", \"eye adaptation\", \"visual acuity\", "
          "\"scotopic vision\",\n              \"overall\"]",
          "categories = [\"overall\"]");
  replace("file = \"scenes/", "file = \"" + std::string(GLARELAB_SOURCE_DIR) + "/examples/scenes/");
  // Half the pixels each way at twice the pitch: the same degrees, a quarter of the glare's work.
  replace("width_px = 1280 ", "width_px = 640 #");
  replace("height_px = 690", "height_px = 345");
  replace("pixel_pitch_mm = 1.7184 ", "pixel_pitch_mm = 3.4368 #");
  const std::filesystem::path experiment = scratch.path() / "luidolt_headset.toml";
  test::write_bytes(experiment.string(), text);

  const std::filesystem::path offscreen_db = scratch.path() / "offscreen.db";
  const ShellRun offscreen = shell("'" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                       "' --display offscreen --observer simulated --db '" + offscreen_db.string() + "'",
                                   scratch.path() / "offscreen.txt");
  ASSERT_EQ(offscreen.exit_code, 0) << offscreen.output;
  EXPECT_EQ(test::RawDb(offscreen_db.string()).rows("SELECT count(*) FROM trials")[0][0], "4");

  if (const auto missing = test::openxr_runtime_missing(true)) GTEST_SKIP() << *missing;
  const std::filesystem::path db = scratch.path() / "headset.db";
  const std::filesystem::path validation = scratch.path() / "validation.txt";
  const ShellRun run = shell("xvfb-run -a -s '-screen 0 1280x1024x24 -noreset' env " + test::monado_environment() +
                                 " XR_CORE_VALIDATION_EXPORT_TYPE=text XR_CORE_VALIDATION_FILE_NAME='" +
                                 validation.string() + "' '" + std::string(GLARELAB_BINARY) + "' run '" +
                                 experiment.string() + "' --observer simulated --db '" + db.string() + "'",
                             scratch.path() / "output.txt");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("Core Validation output type: text"), std::string::npos) << run.output;
  EXPECT_EQ(std::filesystem::exists(validation) ? test::read_bytes(validation.string()) : std::string(), "");
  EXPECT_EQ(run.output.find("VUID"), std::string::npos) << run.output;

  const test::RawDb raw(db.string());
  const auto session = raw.rows("SELECT status, clock FROM sessions");
  ASSERT_EQ(session.size(), 1u);
  EXPECT_EQ(session[0][0], "completed");
  EXPECT_EQ(session[0][1], "predicted");
  // The real lamp's rating first, then the three simulations (Luidolt 2020, 7.2).
  const auto trials = raw.rows("SELECT condition FROM trials ORDER BY trial_index");
  ASSERT_EQ(trials.size(), 4u);
  EXPECT_NE(trials[0][0].find("\"name\":\"real_lamp\""), std::string::npos) << trials[0][0];
  const auto display_event = raw.rows("SELECT message FROM session_events WHERE kind = 'display'");
  ASSERT_EQ(display_event.size(), 1u);
  EXPECT_NE(display_event[0][0].find("system 'Monado: Simulated HMD', 2 views 320x345"), std::string::npos)
      << display_event[0][0];
  // One row per submitted frame: as many rows as head poses located (one per xrEndFrame with a
  // layer), and every flip whole runtime periods after the last.
  const auto frames = raw.rows("SELECT flip_s FROM frames ORDER BY rowid");
  ASSERT_FALSE(frames.empty());
  std::size_t poses = 0;
  for (const auto& event : raw.rows("SELECT message FROM session_events WHERE kind = 'head_poses'")) {
    const std::size_t colon = event[0].find(", ");
    poses += static_cast<std::size_t>(std::stoul(event[0].substr(colon + 2)));
  }
  EXPECT_EQ(poses, frames.size());
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const double periods = (std::stod(frames[i][0]) - std::stod(frames[i - 1][0])) / 0.050;
    EXPECT_GE(std::lround(periods), 1) << "flip " << i;
    EXPECT_NEAR(periods, std::round(periods), 1e-4) << "flip " << i;
  }
}

// The head pose at each submitted frame, one `head_poses` event per trial: as many poses as the
// trial has frames rows, each at its row's flip_s (both are the frame's predicted display time,
// one logged by the session clock, the other by the display), each tracked.
TEST(OpenXrDisplay, HeadPoseOfEveryFrameIsLoggedAtItsFlip) {
  if (const auto missing = test::openxr_runtime_missing(true)) GTEST_SKIP() << *missing;
  const test::ScratchDir scratch;
  const std::filesystem::path experiment = stereo_demo(scratch.path());
  const std::filesystem::path db = scratch.path() / "session.db";
  const ShellRun run = shell("xvfb-run -a -s '-screen 0 1280x1024x24 -noreset' env " + test::monado_environment() +
                                 " '" + std::string(GLARELAB_BINARY) + "' run '" + experiment.string() +
                                 "' --display openxr --observer simulated --stop-after 3 --db '" + db.string() + "'",
                             scratch.path() / "output.txt");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const test::RawDb raw(db.string());
  const auto events = raw.rows("SELECT message FROM session_events WHERE kind = 'head_poses' ORDER BY id");
  ASSERT_EQ(events.size(), 3u);
  for (int trial = 0; trial < 3; ++trial) {
    const std::string& message = events[static_cast<std::size_t>(trial)][0];
    const auto flips = raw.rows("SELECT f.flip_s FROM frames f JOIN trials t ON t.id = f.trial_id WHERE t.trial_index = " +
                                std::to_string(trial) + " ORDER BY f.rowid");
    ASSERT_EQ(message.rfind("trial " + std::to_string(trial) + ", " + std::to_string(flips.size()) + " frames: ", 0), 0u)
        << message;
    EXPECT_EQ(message.find("untracked"), std::string::npos) << message;
    for (const auto& flip : flips) {
      char stamp[32];
      std::snprintf(stamp, sizeof stamp, "%.6f s (", std::stod(flip[0]));
      EXPECT_NE(message.find(stamp), std::string::npos) << stamp << " in " << message;
    }
  }
}

// The frames a headset session draws are those of a side-by-side session on the same seed: the
// first stimulus frame of each trial (after glare, both eyes, linear cd/m2) is the same file bit
// for bit. The views tests below check what reaches each eye: its half of the drawn frame, and of
// a side-by-side session's encoded frame, to the swapchain format's precision.
TEST(OpenXrDisplay, HeadsetSessionDrawsTheSideBySideSessionsFramesBitForBit) {
  if (const auto missing = test::openxr_runtime_missing(true)) GTEST_SKIP() << *missing;
  const test::ScratchDir scratch;
  const std::filesystem::path experiment = stereo_demo(scratch.path());
  const auto arguments = [&](const std::string& name) {
    return "'" + experiment.string() + "' --observer simulated --seed 11 --stop-after 2 --db '" +
           (scratch.path() / (name + ".db")).string() + "' --save-frames '" + (scratch.path() / name).string() + "'";
  };
  const ShellRun headset = shell("xvfb-run -a -s '-screen 0 1280x1024x24 -noreset' env " + test::monado_environment() +
                                     " '" + std::string(GLARELAB_BINARY) + "' run --display openxr " + arguments("openxr"),
                                 scratch.path() / "openxr.txt");
  ASSERT_EQ(headset.exit_code, 0) << headset.output;
  const ShellRun side_by_side = shell("'" + std::string(GLARELAB_BINARY) + "' run --display offscreen " + arguments("sbs"),
                                      scratch.path() / "sbs.txt");
  ASSERT_EQ(side_by_side.exit_code, 0) << side_by_side.output;
  for (const char* frame : {"trial_0000.exr", "trial_0001.exr"}) {
    const std::string shown = test::read_bytes((scratch.path() / "openxr" / frame).string());
    ASSERT_FALSE(shown.empty()) << frame;
    EXPECT_TRUE(shown == test::read_bytes((scratch.path() / "sbs" / frame).string())) << frame;
  }
}

// A pattern drawn straight into the display's frame (frame_framebuffer()): each half in four
// blocks, each block its own grey (k / 255), so a view from the wrong half, a mirrored or shifted
// view, or a wrong encoding shows as a wrong grey.
float block_grey(int eye, int block) { return static_cast<float>(16 + 50 * block + 7 * eye) / 255.0f; }

// The request of a hidden 128 x 64 headset display (two 64 x 64 views) on Monado, whose
// environment it sets in this process.
DisplayRequest small_headset_request() {
  test::set_monado_environment();
  DisplayRequest request;
  request.width_px = 128;
  request.height_px = 64;
  request.visible = false;
  return request;
}

TEST(OpenXrViews, EachViewsSwapchainImageIsItsHalfOfTheFrame) {
  if (const auto missing = test::openxr_runtime_missing(false)) GTEST_SKIP() << *missing;
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "OpenXrViews tests run under xvfb-run (tests/CMakeLists.txt)";
  const DisplayRequest request = small_headset_request();
  auto display = create_display("openxr", request);
  EXPECT_EQ(display->kind(), "openxr");
  EXPECT_NEAR(display->refresh_hz(), 20.0, 1e-6);  // the null compositor's fixed 50 ms period
  const auto* predicting = dynamic_cast<const PredictedFlipSource*>(display.get());
  ASSERT_NE(predicting, nullptr);
  keep_submitted_views(true);
  // Blocks: left and right columns of each half, top and bottom rows (GL rows count from the bottom).
  const int view_w = 64, view_h = 64;
  glEnable(GL_SCISSOR_TEST);
  for (int eye = 0; eye < 2; ++eye)
    for (int block = 0; block < 4; ++block) {
      const int x = eye * view_w + (block % 2) * (view_w / 2);
      const int y_gl = (block / 2 == 0) ? view_h / 2 : 0;  // block 0, 1: top half of the image
      glScissor(x, y_gl, view_w / 2, view_h / 2);
      const float grey = block_grey(eye, block);
      const float colour[4] = {grey, grey, grey, 1.0f};
      glClearNamedFramebufferfv(display->frame_framebuffer(), GL_COLOR, 0, colour);
    }
  glDisable(GL_SCISSOR_TEST);
  std::vector<std::chrono::steady_clock::time_point> predicted;
  display->present();
  predicted.push_back(*predicting->predicted_display_time());
  const std::vector<ImageRGBA> views = last_submitted_views();
  ASSERT_EQ(views.size(), 2u);
  for (int eye = 0; eye < 2; ++eye) {
    const ImageRGBA& view = views[static_cast<std::size_t>(eye)];
    ASSERT_EQ(view.width_px, view_w);
    ASSERT_EQ(view.height_px, view_h);
    for (int y = 0; y < view_h; ++y)
      for (int x = 0; x < view_w; ++x) {
        const int block = (y < view_h / 2 ? 0 : 2) + (x < view_w / 2 ? 0 : 1);
        const float expected = block_grey(eye, block);
        const float* pixel = view.pixel(x, y);
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(pixel[c], expected, 1e-3 * expected) << "eye " << eye << " pixel " << x << "," << y;
      }
  }
  // Two more frames: their predicted display times one period apart.
  for (int frame = 0; frame < 2; ++frame) {
    display->present();
    predicted.push_back(*predicting->predicted_display_time());
  }
  for (std::size_t i = 1; i < predicted.size(); ++i) {
    const double step_s = std::chrono::duration<double>(predicted[i] - predicted[i - 1]).count();
    EXPECT_NEAR(step_s / 0.050, std::round(step_s / 0.050), 1e-4) << step_s;
    EXPECT_GE(std::lround(step_s / 0.050), 1) << step_s;
  }
  keep_submitted_views(false);
}

// A closed display destroys its OpenXR instance. The loader allows one live instance a process
// (a second xrCreateInstance gives XR_ERROR_LIMIT_REACHED, -10, checked first), so a display opened
// after another was closed starts only if the first one's instance was destroyed. This stands in
// for the leak check that scripts/lsan_suppressions.txt gives up for the loader (whose own
// allocations outlive xrDestroyInstance).
TEST(OpenXrViews, AClosedDisplayDestroysItsInstanceSoTheNextOneOpens) {
  if (const auto missing = test::openxr_runtime_missing(false)) GTEST_SKIP() << *missing;
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "OpenXrViews tests run under xvfb-run (tests/CMakeLists.txt)";
  const DisplayRequest request = small_headset_request();
  {
    auto first = create_display("openxr", request);
    try {
      auto second = create_display("openxr", request);
      ADD_FAILURE() << "a second display opened beside a live one";
    } catch (const DisplayError& error) {
      // XR_ERROR_LIMIT_REACHED, named by number before an instance exists to name it.
      EXPECT_NE(std::string(error.what()).find("xrCreateInstance: XrResult -10)"), std::string::npos) << error.what();
    }
  }
  for (int reopened = 0; reopened < 2; ++reopened) {
    auto display = create_display("openxr", request);
    EXPECT_EQ(display->kind(), "openxr");
    display->present();
  }
}

// Acceptance 2 of the headset display: each eye's swapchain image, read back on the client side,
// is that eye's half of a side-by-side session of the same seed and views to 1e-3 relative. The
// headset session runs here (in this process, so its swapchain images can be read back) through
// trial 0; the side-by-side session is the same experiment offscreen on OSMesa's 32-bit float
// buffer, previewed at each condition's first trial (runner/session/stimulus_preview.h: the frame a
// seeded session shows, by construction), so its trial 0 frame's encoded drive values are there
// unrounded. The swapchain is RGBA16F and holds linear values (openxr_view.frag): half float keeps
// 11 significant bits (a rounding is at most 2^-11 = 4.9e-4 relative; the shader's sRGB decode adds
// its pow's error, which llvmpipe's approximation makes the larger part), and below 2^-14 its
// subnormal step of 6e-8 linear (7.7e-7 in drive values through the sRGB curve's 12.92 slope)
// bounds it instead: the tolerance is 1e-3 relative or 1e-6 absolute, whichever is larger. The frame's drive values are not on the 8-bit grid (checked), so a view that went through
// an 8-bit buffer (up to 0.5/255 off) would fail.
TEST(OpenXrViews, EachEyesSwapchainImageIsItsHalfOfASideBySideSessionOfTheSameSeed) {
  if (const auto missing = test::openxr_runtime_missing(false)) GTEST_SKIP() << *missing;
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "OpenXrViews tests run under xvfb-run (tests/CMakeLists.txt)";
  test::set_monado_environment();
  const test::ScratchDir scratch;
  const std::filesystem::path experiment = stereo_demo(scratch.path());
  std::ostringstream progress;

  RunOptions headset;
  headset.experiment_path = experiment.string();
  headset.db_path = (scratch.path() / "openxr.db").string();
  headset.display = "openxr";
  headset.observer = "simulated";
  headset.seed = 11;
  headset.stop_after_trials = 1;
  keep_submitted_views(true);
  run_session(headset, progress);
  const std::vector<std::vector<ImageRGBA>> submitted = submitted_views();
  keep_submitted_views(false);
  // One submitted frame per frames row, in order: the first is trial 0's first stimulus frame.
  const test::RawDb raw(headset.db_path);
  const auto frames = raw.rows("SELECT t.trial_index, f.frame_index FROM frames f JOIN trials t ON t.id = f.trial_id "
                               "ORDER BY f.rowid");
  ASSERT_EQ(submitted.size(), frames.size()) << progress.str();
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(frames[0][0], "0");
  EXPECT_EQ(frames[0][1], "0");

  RunOptions side_by_side;
  side_by_side.experiment_path = experiment.string();
  side_by_side.db_path = (scratch.path() / "preview.db").string();
  side_by_side.display = "osmesa";
  side_by_side.observer = "simulated";
  side_by_side.seed = 11;
  StimulusPreview preview;
  preview.conditions = {"ratio_1.05", "ratio_1.15", "ratio_1.30", "ratio_1.60", "ratio_2.00"};
  side_by_side.preview = preview;
  const RunResult previewed = run_session(side_by_side, progress);
  const PreviewFrame* trial_0 = nullptr;
  for (const PreviewFrame& frame : previewed.previews)
    if (frame.plan.trial_index == 0) trial_0 = &frame;
  ASSERT_NE(trial_0, nullptr) << "the preview captured no frame of trial 0";
  const ImageRGBA& reference = trial_0->display_drive;
  ASSERT_EQ(reference.width_px, 1024);
  ASSERT_EQ(reference.height_px, 551);

  const std::vector<ImageRGBA>& views = submitted[0];
  ASSERT_EQ(views.size(), 2u);
  double worst_relative = 0.0;
  double worst_off_grid = 0.0;  // how far the reference lies from the 8-bit grid, relative
  for (int eye = 0; eye < 2; ++eye) {
    const ImageRGBA& view = views[static_cast<std::size_t>(eye)];
    ASSERT_EQ(view.width_px, 512);
    ASSERT_EQ(view.height_px, 551);
    for (int y = 0; y < view.height_px; ++y)
      for (int x = 0; x < view.width_px; ++x)
        for (int c = 0; c < 3; ++c) {
          const double expected = reference.pixel(eye * 512 + x, y)[c];
          const double got = view.pixel(x, y)[c];
          ASSERT_LE(std::abs(got - expected), std::max(1e-3 * std::abs(expected), 1e-6))
              << "eye " << eye << " pixel " << x << "," << y << " channel " << c << ": " << got << " against " << expected;
          if (expected > 1e-3) {
            worst_relative = std::max(worst_relative, std::abs(got - expected) / expected);
            worst_off_grid = std::max(worst_off_grid, std::abs(expected - std::round(expected * 255.0) / 255.0) / expected);
          }
        }
  }
  EXPECT_GT(worst_off_grid, 1e-3) << "the frame's drive values lie on the 8-bit grid: an 8-bit path would pass too";
  std::printf("[          ] worst relative difference %.3g (8-bit grid up to %.3g away)\n", worst_relative, worst_off_grid);
}

// Trials stored so far in a database another process is writing; -1 while it cannot be read.
int stored_trials(const std::filesystem::path& db) {
  if (!std::filesystem::exists(db)) return -1;
  sqlite3* connection = nullptr;
  int count = -1;
  if (sqlite3_open_v2(db.c_str(), &connection, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_busy_timeout(connection, 1000);
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(connection, "SELECT count(*) FROM trials", -1, &statement, nullptr) == SQLITE_OK &&
        sqlite3_step(statement) == SQLITE_ROW)
      count = sqlite3_column_int(statement, 0);
    sqlite3_finalize(statement);
  }
  sqlite3_close_v2(connection);
  return count;
}

// Acceptance 3: a session the runtime ends mid-trial is stored aborted with every answered trial,
// under the runtime's reason, and resumes to completion. Monado in-process ends a session only when
// asked to (xrRequestExitSession; it has no outside hook to end one), so the experimenter's Escape in
// the mirror window asks it, as a headset's own way out: the runtime then goes through STOPPING,
// which ends the session as SteamVR's "quit" or a headset taken away would. Ten trials of ten
// stimulus frames (half a second each at Monado's 20 Hz); Escape after the second is stored.
TEST(OpenXrViews, ASessionTheRuntimeEndsIsStoredAbortedAndResumesToCompletion) {
  if (const auto missing = test::openxr_runtime_missing(false)) GTEST_SKIP() << *missing;
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "OpenXrViews tests run under xvfb-run (tests/CMakeLists.txt)";
  if (std::system("command -v xdotool > /dev/null") != 0) GTEST_SKIP() << "xdotool is missing (scripts/setup.sh)";
  test::set_monado_environment();
  const test::ScratchDir scratch;
  const std::filesystem::path experiment =
      stereo_demo(scratch.path(), {{"stimulus_frames", "stimulus_frames = 10"}});
  const std::filesystem::path db = scratch.path() / "session.db";
  const std::filesystem::path output = scratch.path() / "output.txt";
  {
    test::GlarelabProcess process(
        {"run", experiment.string(), "--display", "openxr", "--observer", "simulated", "--db", db.string()}, output);
    ASSERT_TRUE(process.started());
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (stored_trials(db) < 2 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_GE(stored_trials(db), 2) << test::read_bytes(output.string());
    ASSERT_EQ(std::system((test::focus_window_command("OpenXR mirror", 20) + " && xdotool key Escape").c_str()), 0);
    EXPECT_EQ(process.wait(), 130) << test::read_bytes(output.string());
  }
  const std::string said = test::read_bytes(output.string());
  EXPECT_NE(said.find("note: OpenXR: the OpenXR runtime stopped the session (exit requested with Escape in the mirror "
                      "window); the session ends"),
            std::string::npos)
      << said;
  std::string session_id;
  int answered = 0;
  {
    const test::RawDb raw(db.string());
    const auto session = raw.rows("SELECT id, status FROM sessions");
    ASSERT_EQ(session.size(), 1u);
    session_id = session[0][0];
    EXPECT_EQ(session[0][1], "aborted");
    EXPECT_EQ(raw.value("SELECT message FROM session_events WHERE kind = 'aborted'"),
              "the OpenXR runtime stopped the session (exit requested with Escape in the mirror window)");
    answered = std::stoi(raw.value("SELECT count(*) FROM trials"));
    EXPECT_GE(answered, 2);
    EXPECT_LT(answered, 10) << "the runtime ended the session before its last trial";
    // Every stored trial is answered, in order.
    EXPECT_EQ(raw.value("SELECT count(*) FROM trials WHERE response IS NULL OR response = ''"), "0");
    EXPECT_EQ(raw.value("SELECT max(trial_index) FROM trials"), std::to_string(answered - 1));
  }
  test::GlarelabProcess resumed({"run", experiment.string(), "--display", "openxr", "--observer", "simulated", "--db",
                                 db.string(), "--resume", session_id},
                                scratch.path() / "resumed.txt");
  ASSERT_TRUE(resumed.started());
  EXPECT_EQ(resumed.wait(), 0) << test::read_bytes((scratch.path() / "resumed.txt").string());
  const test::RawDb raw(db.string());
  EXPECT_EQ(raw.value("SELECT status FROM sessions"), "completed");
  EXPECT_EQ(raw.value("SELECT count(*) FROM trials"), "10");
  EXPECT_EQ(raw.value("SELECT count(DISTINCT trial_index) FROM trials"), "10");
}

}  // namespace
}  // namespace glarelab
