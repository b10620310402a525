// A whole session in a real X window (under xvfb-run), answered with key presses sent by xdotool,
// then ended with Escape: the answered trials are kept and the session is marked aborted.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cstdlib>

#include "cli_process.h"
#include "window_focus.h"
#include "runner/store/result_store.h"

namespace glarelab {
namespace {

int shell(const std::string& command) { return std::system(command.c_str()); }

TEST(WindowBackend, KeyboardAnswersThenEscapeAborts) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  ASSERT_EQ(shell("command -v xdotool > /dev/null"), 0) << "xdotool is needed (scripts/setup.sh installs it)";
  const test::ScratchDir scratch;
  // Without glare (every row control): each trial starts at once, so the timed key presses below
  // answer the trials in order even on a loaded machine.
  test::write_demo_conditions_without_glare(scratch.path() / "conditions.csv");
  const auto experiment = test::demo_variant(scratch.path(), {{"file", "file = \"" + (scratch.path() / "conditions.csv").string() + "\""},
                                                              {"width_px", "width_px = 512"},
                                                              {"height_px", "height_px = 256"},
                                                              {"stimulus_frames", "stimulus_frames = 6"}});
  const auto db = scratch.path() / "keyboard.db";
  test::GlarelabProcess process({"run", experiment.string(), "--display", "window", "--observer", "keyboard", "--db",
                                 db.string(), "--participant", "kb"},
                                scratch.path() / "out.txt");
  ASSERT_TRUE(process.started());
  // Wait for the window, give it the keyboard focus, then answer three trials and press Escape.
  ASSERT_EQ(shell(test::focus_window_command("glarelab: demo", 20)), 0)
      << test::read_bytes((scratch.path() / "out.txt").string());
  const std::vector<std::string> keys = {"Right", "Left", "2"};
  for (const auto& key : keys) {
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    ASSERT_EQ(shell("xdotool key " + key), 0);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  ASSERT_EQ(shell("xdotool key Escape"), 0);
  EXPECT_EQ(process.wait(), 130) << test::read_bytes((scratch.path() / "out.txt").string());

  const ResultStore store(db.string());
  const auto session = store.load_sessions().at(0);
  EXPECT_EQ(session.status, "aborted");
  EXPECT_EQ(session.display_backend, "window");
  EXPECT_EQ(session.clock, "monotonic");
  const auto trials = store.load_trials(session.id);
  ASSERT_EQ(trials.size(), 3u);
  EXPECT_EQ(trials[0].response, "right");
  EXPECT_EQ(trials[1].response, "left");
  EXPECT_EQ(trials[2].response, "right");  // "2" is the second response
  for (const auto& trial : trials) {
    ASSERT_TRUE(trial.response_time_s.has_value());
    EXPECT_GT(*trial.response_time_s, 0.0);
    // Six stimulus frames; the response screen's flips follow with negative frame indices.
    const auto frames = store.load_frames(trial.id);
    EXPECT_EQ(std::count_if(frames.begin(), frames.end(), [](const FrameRecord& f) { return f.frame_index >= 0; }), 6);
    for (std::size_t f = 0; f < frames.size(); ++f) {
      EXPECT_EQ(frames[f].frame_index, f < 6 ? static_cast<int>(f) : -static_cast<int>(f - 5));
      if (f > 0) {
        EXPECT_GT(frames[f].flip_s, frames[f - 1].flip_s);
      }
    }
  }
  EXPECT_EQ(store.integrity_check(), "ok");
}

// An instructions screen waits for Space or Enter; other keys are logged and ignored, and do not
// answer the first trial.
TEST(WindowBackend, SpaceContinuesTheInstructionsScreen) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  ASSERT_EQ(shell("command -v xdotool > /dev/null"), 0) << "xdotool is needed (scripts/setup.sh installs it)";
  const test::ScratchDir scratch;
  test::write_demo_conditions_without_glare(scratch.path() / "conditions.csv");
  auto experiment = test::demo_variant(scratch.path(), {{"file", "file = \"" + (scratch.path() / "conditions.csv").string() + "\""},
                                                        {"width_px", "width_px = 512"},
                                                        {"height_px", "height_px = 256"},
                                                        {"stimulus_frames", "stimulus_frames = 6"}});
  test::write_bytes(experiment.string(), test::read_bytes(experiment.string()) +
                                             "\n[presentation]\ninstructions = \"Press Space to start\"\n"
                                             "screen_min_frames = 1\n");
  const auto db = scratch.path() / "screen.db";
  test::GlarelabProcess process({"run", experiment.string(), "--display", "window", "--observer", "keyboard", "--db",
                                 db.string()},
                                scratch.path() / "out.txt");
  ASSERT_TRUE(process.started());
  ASSERT_EQ(shell(test::focus_window_command("glarelab: demo", 20)), 0)
      << test::read_bytes((scratch.path() / "out.txt").string());
  for (const std::string key : {"Left", "space", "Right", "Escape"}) {
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    ASSERT_EQ(shell("xdotool key " + key), 0);
  }
  EXPECT_EQ(process.wait(), 130) << test::read_bytes((scratch.path() / "out.txt").string());

  const ResultStore store(db.string());
  const auto trials = store.load_trials(1);
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].response, "right") << "'Left' was pressed on the screen, before the trial";
  const auto frames = store.load_frames(trials[0].id);
  ASSERT_FALSE(frames.empty());
  EXPECT_LT(frames.front().frame_index, 0) << "the screen's flips come first";
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(store.handle(), "SELECT kind || ': ' || message FROM session_events ORDER BY id", -1, &statement,
                     nullptr);
  std::string log;
  while (sqlite3_step(statement) == SQLITE_ROW) log += reinterpret_cast<const char*>(sqlite3_column_text(statement, 0)) + std::string("\n");
  sqlite3_finalize(statement);
  EXPECT_NE(log.find("ignored_key: trial 0 instructions screen: key 'left' does not continue (Space or Enter)"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("screen: trial 0, instructions: 'Press Space to start' shown "), std::string::npos) << log;
}

}  // namespace
}  // namespace glarelab
