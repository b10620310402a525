// The double-adjustment example in a real X window (under xvfb-run), adjusted with keys and
// mouse-wheel clicks sent by xdotool: the recorded settings are the start values times
// 10^(the hand-summed log10 steps). An optional response device that is absent is logged and
// the keyboard and wheel go on.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "cli_process.h"
#include "window_focus.h"
#include "runner/store/result_store.h"
#include "session_events.h"

namespace glarelab {
namespace {

int shell(const std::string& command) { return std::system(command.c_str()); }

// examples/ritschel_adjustment.toml on a small screen, without glare (every trial then starts at
// once, so timed inputs reach the trial they are meant for), three stimulus frames.
std::filesystem::path small_adjustment_example(const std::filesystem::path& dir) {
  const std::filesystem::path examples = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples";
  std::istringstream in(test::read_bytes((examples / "ritschel_adjustment.toml").string()));
  std::ostringstream out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("width_px", 0) == 0) line = "width_px = 512";
    if (line.rfind("height_px", 0) == 0) line = "height_px = 256";
    if (line.rfind("stimulus_duration_s", 0) == 0) line = "stimulus_duration_s = 0.05";
    for (const char* mode : {"\"static\"", "\"dynamic\""})
      for (auto at = line.find(mode); at != std::string::npos; at = line.find(mode)) line.replace(at, std::string(mode).size(), "\"control\"");
    if (const auto at = line.find("\"scenes/"); at != std::string::npos) line.replace(at, 1, "\"" + examples.string() + "/");
    out << line << "\n";
  }
  const auto path = dir / "adjustment.toml";
  test::write_bytes(path.string(), out.str());
  return path;
}

double condition_number(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\":");
  if (at == std::string::npos) return NAN;
  std::size_t begin = at + key.size() + 3;
  while (json[begin] == ' ' || json[begin] == '"') ++begin;
  return std::stod(json.substr(begin));
}

TEST(WindowBackend, AdjustmentWithKeysAndWheelStepsInLogUnits) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  ASSERT_EQ(shell("command -v xdotool > /dev/null"), 0) << "xdotool is needed (scripts/setup.sh installs it)";
  const test::ScratchDir scratch;
  const auto experiment = small_adjustment_example(scratch.path());
  const auto db = scratch.path() / "adjustment.db";
  // An optional device that is absent (no HID device has these ids): the keyboard and wheel go on.
  test::GlarelabProcess process({"run", experiment.string(), "--display", "window", "--db", db.string(),
                                 "--response-device", "fffe:fffd", "--buttons", "1:0=up,1:1=down,1:2=accept",
                                 "--response-device-optional"},
                                scratch.path() / "out.txt");
  ASSERT_TRUE(process.started());
  // Focus the window and put the pointer over it (wheel clicks go to the window under the pointer).
  ASSERT_EQ(shell(test::focus_window_command("glarelab: ritschel-2009-adjustment", 20) +
                  " && xdotool search --onlyvisible --name 'glarelab: ritschel-2009-adjustment' "
                  "mousemove --window %1 100 100 > /dev/null"),
            0)
      << test::read_bytes((scratch.path() / "out.txt").string());
  // coarse 0.1, fine 0.01 (the example's steps):
  //  trial 0: Up Up (+0.2), wheel up (+0.1), Shift+wheel down (-0.01), Right Right (+0.02): +0.31
  //  trial 1: Down (-0.1), F (fine mode), 3 wheel ups (+0.03), Up (+0.01), Left (-0.01): -0.07
  const std::vector<std::string> trials = {
      "xdotool key Up Up && xdotool click 4 && xdotool keydown shift && xdotool click 5 && xdotool keyup shift && "
      "xdotool key Right Right Return",
      "xdotool key Down f && xdotool click --repeat 3 4 && xdotool key Up Left Return",
  };
  const std::vector<double> expected_log10 = {0.31, -0.07};
  for (const auto& inputs : trials) {
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    ASSERT_EQ(shell(inputs), 0);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  ASSERT_EQ(shell("xdotool key Escape"), 0);
  EXPECT_EQ(process.wait(), 130) << test::read_bytes((scratch.path() / "out.txt").string());

  const ResultStore store(db.string());
  const auto session = store.load_sessions().at(0);
  EXPECT_EQ(session.status, "aborted");
  EXPECT_EQ(session.observer, "keyboard");
  const std::vector<std::string> absent_events = test::session_event_messages(store, "response_device_absent");
  ASSERT_EQ(absent_events.size(), 1u);
  const std::string& absent = absent_events[0];
  EXPECT_NE(absent.find("HID: no device fffe:fffd"), std::string::npos) << absent;
  const auto recorded = store.load_trials(session.id);
  ASSERT_EQ(recorded.size(), 2u) << test::read_bytes((scratch.path() / "out.txt").string());
  for (std::size_t k = 0; k < recorded.size(); ++k) {
    const auto settings = store.load_adjustments(recorded[k].id);
    ASSERT_EQ(settings.size(), 2u);
    const double factor = std::pow(10.0, expected_log10[k]);
    const double start_left = condition_number(recorded[k].condition, "start_left_cd_m2");
    const double start_right = condition_number(recorded[k].condition, "start_right_cd_m2");
    EXPECT_NEAR(settings[0].value_cd_m2 / (start_left * factor), 1.0, 1e-12) << recorded[k].condition;
    EXPECT_NEAR(settings[1].value_cd_m2 / (start_right * factor), 1.0, 1e-12) << recorded[k].condition;
    // Every flip is in `frames`: the three stimulus frames, then the adjustment phase's flips
    // (frame_index -1, -2, ... in flip order) until the setting was accepted.
    const auto frames = store.load_frames(recorded[k].id);
    ASSERT_GT(frames.size(), 3u);
    for (std::size_t f = 0; f < frames.size(); ++f) {
      EXPECT_EQ(frames[f].frame_index, f < 3 ? static_cast<int>(f) : -static_cast<int>(f - 2));
      if (f > 0) {
        EXPECT_GT(frames[f].flip_s, frames[f - 1].flip_s);
      }
    }
  }
  EXPECT_EQ(store.integrity_check(), "ok");
}

}  // namespace
}  // namespace glarelab
