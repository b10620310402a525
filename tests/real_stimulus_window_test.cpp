// A rating session with a real-stimulus condition in a real X window (under xvfb-run), answered
// with digit keys sent by xdotool: the real lamp's trial shows the instruction naming it (the
// frame the window was sent, saved by --save-frames, holds its raster at the centre) and both
// ratings are stored.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "cli_process.h"
#include "core/exr_io.h"
#include "instruction_frame.h"
#include "runner/store/result_store.h"
#include "window_focus.h"

namespace glarelab {
namespace {

int shell(const std::string& command) { return std::system(command.c_str()); }

TEST(WindowBackend, RealStimulusShowsItsInstructionAndTakesAKeyboardRating) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  ASSERT_EQ(shell("command -v xdotool > /dev/null"), 0) << "xdotool is needed (scripts/setup.sh installs it)";
  const test::ScratchDir scratch;
  const std::string scenes = std::string(GLARELAB_SOURCE_DIR) + "/examples/scenes/";
  // The real lamp first (a fixed first block), then its simulation, as in Luidolt 2020, 7.2.
  const std::string file = scratch.write(
      "real_window.toml",
      "[experiment]\nname = \"real-window\"\nseed = 11\n"
      "[display]\nwidth_px = 640\nheight_px = 256\nviewing_distance_mm = 600.0\npixel_pitch_mm = 0.25\n"
      "peak_luminance_cd_m2 = 250.0\n"
      "[scenes]\nlamp = { file = \"" + scenes + "lamp_100.exr\" }\n"
      "[procedure]\ntype = \"rating\"\ncategories = [\"overall\"]\nscale_points = 7\nstimulus_frames = 6\n"
      "block_order = \"fixed\"\n"
      "[[blocks]]\nname = \"real light\"\nconditions = [\"real lamp\"]\n"
      "[[blocks]]\nname = \"simulation\"\nconditions = [\"simulated lamp\"]\n"
      "[[conditions.rows]]\nname = \"real lamp\"\nscene = \"real:desk lamp\"\n"
      "[[conditions.rows]]\nname = \"simulated lamp\"\nscene = \"lamp\"\n");
  const auto db = scratch.path() / "window.db";
  const auto frames = scratch.path() / "frames";
  test::GlarelabProcess process({"run", file, "--display", "window", "--observer", "keyboard", "--db", db.string(),
                                 "--save-frames", frames.string()},
                                scratch.path() / "out.txt");
  ASSERT_TRUE(process.started());
  ASSERT_EQ(shell(test::focus_window_command("glarelab: real-window", 20)), 0)
      << test::read_bytes((scratch.path() / "out.txt").string());
  // Control conditions start at once: keys 600 ms apart answer the trials in order.
  for (const std::string key : {"6", "3"}) {
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    ASSERT_EQ(shell("xdotool key " + key), 0);
  }
  EXPECT_EQ(process.wait(), 0) << test::read_bytes((scratch.path() / "out.txt").string());

  const ResultStore store(db.string());
  const auto session = store.load_sessions().at(0);
  EXPECT_EQ(session.status, "completed");
  EXPECT_EQ(session.display_backend, "window");
  const auto trials = store.load_trials(session.id);
  ASSERT_EQ(trials.size(), 2u);
  EXPECT_EQ(trials[0].condition, "{\"name\":\"real lamp\",\"scene\":\"real:desk lamp\",\"category\":\"overall\","
                                 "\"stimulus\":\"real\"}");
  EXPECT_EQ(trials[0].response, "6");
  ASSERT_TRUE(trials[0].response_time_s.has_value());
  EXPECT_GT(*trials[0].response_time_s, 0.0);
  EXPECT_EQ(trials[1].condition, "{\"name\":\"simulated lamp\",\"scene\":\"lamp\",\"category\":\"overall\"}");
  EXPECT_EQ(trials[1].response, "3");

  // Lines 0.6 degrees high (2 x 600 mm x tan(0.3 deg) / 0.25 mm = 25.1 px, drawn 25), wrapped
  // within 90 % of 640 px, at [presentation]'s default 100 cd/m2.
  const ImageRGBA real = read_exr((frames / "trial_0000.exr").string()).image;
  const ImageRGBA simulated = read_exr((frames / "trial_0001.exr").string()).image;
  const std::string instruction = "Look at the real desk lamp, then answer.";
  EXPECT_LT(test::centred_text_mismatch_cd_m2(real, instruction, 25.0, 576.0, 100.0), 1e-3);
  EXPECT_GT(test::centred_text_mismatch_cd_m2(simulated, instruction, 25.0, 576.0, 100.0), 10.0);
}

}  // namespace
}  // namespace glarelab
