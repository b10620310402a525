// `glarelab calibrate --display window` in a real X window (under xvfb-run, tests/CMakeLists.txt),
// the readings typed at the terminal as a person would (one line per patch, "b" to go back and
// measure a patch again), and Escape in the window ending it with nothing written.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "cli_process.h"
#include "core/display_calibration.h"
#include "scratch_dir.h"
#include "window_focus.h"

namespace glarelab {
namespace {

int shell(const std::string& command) { return std::system(command.c_str()); }

TEST(WindowBackendCalibrate, ReadingsTypedAtTheTerminalWithOneGoneBackOverWriteTheTable) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  const test::ScratchDir dir;
  const std::string table = dir.file("display.csv");
  const std::string output = dir.file("out.txt");
  // Two levels: red 0.2 and 50; green 0.2 and 5, then "b" back to green's full drive, read again as
  // 180; blue 0.2 and 18; white 0.2 and 248 (0.4 cd/m2 over the table's 0.2 + 49.8 + 179.8 + 17.8).
  const std::string typed = "0.2\\n50\\n0.2\\n5\\nb\\n180\\n0.2\\n18\\n0.2\\n248\\n";
  const int status = shell("printf '" + typed + "' | '" + std::string(GLARELAB_BINARY) +
                           "' calibrate --display window --levels 2 --width 160 --height 120 --out '" + table +
                           "' > '" + output + "' 2>&1");
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0) << test::read_bytes(output);
  const DisplayCalibration calibration = read_display_calibration(table);
  ASSERT_EQ(calibration.rows(), 2u);
  EXPECT_EQ(calibration.luminance_cd_m2[0][1], 50.0);
  EXPECT_EQ(calibration.luminance_cd_m2[1][1], 180.0) << "the reading typed after going back replaces the first";
  EXPECT_EQ(calibration.luminance_cd_m2[2][1], 18.0);
  EXPECT_EQ(calibration.peak_cd_m2(), 0.2 + 49.8 + 179.8 + 17.8);
  const std::string text = test::read_bytes(output);
  EXPECT_THAT(text, ::testing::HasSubstr("[4/8] green level 2 of 2 (code 255 of 255) (was 5)"));
  // Two levels leave one point above black per channel: no slope to fit, and the report says so.
  EXPECT_THAT(text, ::testing::HasSubstr("gamma not fitted (1 level(s) above 1% of the full gain; 2 needed)"));
  EXPECT_THAT(text, ::testing::HasSubstr("peak 247.6 cd/m2 (black + the three gains); white measured 248 cd/m2 (+0.16 %: additivity)"));
}

TEST(WindowBackendCalibrate, EscapeInTheWindowStopsWithNothingWritten) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  ASSERT_EQ(shell("command -v xdotool > /dev/null"), 0) << "xdotool is needed (scripts/setup.sh installs it)";
  const test::ScratchDir dir;
  const std::string table = dir.file("display.csv");
  test::GlarelabProcess process({"calibrate", "--display", "window", "--width", "160", "--height", "120", "--out", table},
                                dir.path() / "out.txt");
  ASSERT_TRUE(process.started());
  ASSERT_EQ(shell(test::focus_window_command("glarelab: calibrate", 30)), 0)
      << test::read_bytes((dir.path() / "out.txt").string());
  ASSERT_EQ(shell("xdotool key Escape"), 0);
  EXPECT_EQ(process.wait(), 130) << test::read_bytes((dir.path() / "out.txt").string());
  EXPECT_THAT(test::read_bytes((dir.path() / "out.txt").string()),
              ::testing::HasSubstr("calibrate: stopped (Escape pressed): nothing written"));
  EXPECT_FALSE(std::filesystem::exists(table));
}

}  // namespace
}  // namespace glarelab
