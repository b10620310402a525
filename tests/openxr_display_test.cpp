// The OpenXR display (`--display openxr`) against a real runtime, Monado's simulated headset with
// its null compositor (tests/openxr_runtime.h), with the core validation layer on: a whole session
// stores every trial and one frames row per submitted frame, stamped with predicted display times
// one runtime period (50 ms) apart; each view's swapchain image, read back on the client side, is
// its half of the side-by-side frame, and the frames drawn are a side-by-side session's; and
// without a runtime the run exits 3 naming OpenXR and quoting the loader. The OpenXrViews suite makes the display in this process and runs under Xvfb
// (tests/CMakeLists.txt); the others start glarelab under xvfb-run themselves.
#include <gtest/gtest.h>

#include <glad/gl.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_process.h"
#include "openxr_runtime.h"
#include "raw_db.h"
#include "runner/display/display_backend.h"
#include "runner/display/openxr_clock.h"
#include "runner/display/openxr_display.h"

namespace glarelab {
namespace {

// The demo's lamps side by side in each eye's half: a stereo display 1024 x 256 (two 512 x 256
// views), two stimulus frames a trial, five rows x two sides = 10 trials.
std::filesystem::path stereo_demo(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  test::write_demo_conditions_without_glare(dir / "conditions.csv");
  return test::demo_variant(dir, {{"file", "file = \"" + (dir / "conditions.csv").string() + "\""},
                                  {"width_px", "width_px = 1024"},
                                  {"height_px", "height_px = 256"},
                                  {"encoding", "encoding = \"srgb\"\nstereo = \"side_by_side\""},
                                  {"stimulus_frames", "stimulus_frames = 2"},
                                  {"question", "question = \"\""},
                                  {"wavelength_samples", "wavelength_samples = 8"}});
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
  EXPECT_NE(display_event[0][0].find("system 'Monado: Simulated HMD', 2 views 512x256"), std::string::npos)
      << display_event[0][0];

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
// for bit. With the views test below (each swapchain image is its half of the drawn frame), what
// reaches each eye is that eye's half of the side-by-side session, up to the mirror window's 8 bits.
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

// A pattern drawn straight into the mirror's default framebuffer: each half in four blocks, each
// block its own grey (k / 255: exact in the 8-bit window), so a view from the wrong half, a
// mirrored or shifted view, or a wrong encoding shows as a wrong grey.
float block_grey(int eye, int block) { return static_cast<float>(16 + 50 * block + 7 * eye) / 255.0f; }

TEST(OpenXrViews, EachViewsSwapchainImageIsItsHalfOfTheFrame) {
  if (const auto missing = test::openxr_runtime_missing(false)) GTEST_SKIP() << *missing;
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "OpenXrViews tests run under xvfb-run (tests/CMakeLists.txt)";
  test::set_monado_environment();
  DisplayRequest request;
  request.width_px = 128;
  request.height_px = 64;
  request.visible = false;
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
      glClearNamedFramebufferfv(0, GL_COLOR, 0, colour);
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

}  // namespace
}  // namespace glarelab
