// Answers from a headset's controllers (docs/STEREO.md, "Controllers") against a real runtime:
// Monado's remote driver (tests/openxr_runtime.h), whose two Valve Index controllers this test
// presses over its TCP hub while a keyboard-observer session runs in the headset under Xvfb with the
// core validation layer. A press continues the instructions; each trial's answer is the hand the test pressed (left hand: the first
// response, right hand: the second), its response time counts to the press the runtime saw, and
// every press is logged with its button; the menu button (B) gives the third response, which a
// two-alternative choice does not have.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "cli_process.h"
#include "monado_remote.h"
#include "openxr_runtime.h"
#include "raw_db.h"

namespace glarelab {
namespace {

using test::free_port;
using test::RemoteController;
using test::RemoteData;
using test::resting_state;
using test::send_state;

TEST(OpenXrControllers, PressesAnswerTrialsLikeKeysAndAreLoggedWithTheirButton) {
  if (const auto missing = test::monado_remote_missing()) GTEST_SKIP() << *missing;
  const test::ScratchDir scratch;
  std::filesystem::create_directories(scratch.path());
  test::write_demo_conditions_without_glare(scratch.path() / "conditions.csv");
  // The demo's lamps in the headset: halves of 512 x 551 px at the pitch that spans the remote
  // headset's views (85 deg across, as the simulated one's: docs/STEREO.md).
  const std::filesystem::path experiment =
      test::demo_variant(scratch.path(), {{"file", "file = \"" + (scratch.path() / "conditions.csv").string() +
                                                       "\"\n\n[presentation]\ninstructions = \"Press a trigger to "
                                                       "begin.\"\nscreen_min_frames = 4\ntext_height_deg = 2.0"},
                                          {"width_px", "width_px = 1024"},
                                          {"height_px", "height_px = 551"},
                                          {"pixel_pitch_mm", "pixel_pitch_mm = 2.1477"},
                                          {"encoding", "encoding = \"srgb\"\nstereo = \"side_by_side\""},
                                          {"stimulus_frames", "stimulus_frames = 2"},
                                          {"question", "question = \"\""}});
  const std::filesystem::path db = scratch.path() / "session.db";
  const std::filesystem::path validation = scratch.path() / "validation.txt";
  const int port = free_port();
  ASSERT_GT(port, 0);
  // Presses in turn: the right hand's trigger, the left's, the right's B (menu); each held 0.2 s
  // (4 of the null compositor's 50 ms frames), 0.3 s apart, until the session has ended.
  std::map<std::string, int> pressed;  // button as the session logs it -> presses sent
  const test::RemoteSessionRun run = test::run_with_remote_hub(
      scratch.path(), port, /*eye_gaze=*/false, 180,
      "run '" + experiment.string() + "' --display openxr --stop-after 4 --db '" + db.string() + "'", validation,
      [&](int fd, const std::atomic<bool>& done) {
        RemoteData state = resting_state();
        send_state(fd, state);
        for (int k = 0; !done; ++k) {
          const char* button = k % 3 == 0 ? "right hand select" : k % 3 == 1 ? "left hand select" : "menu";
          RemoteController& hand = k % 3 == 1 ? state.left : state.right;
          if (k % 3 == 2) {
            hand.b_click = true;
          } else {
            hand.trigger_click = true;
            hand.trigger_value = 1.0f;
          }
          if (!send_state(fd, state)) break;
          ++pressed[button];
          std::this_thread::sleep_for(std::chrono::milliseconds(200));
          hand.b_click = hand.trigger_click = false;
          hand.trigger_value = 0.0f;
          if (!send_state(fd, state)) break;
          std::this_thread::sleep_for(std::chrono::milliseconds(300));
        }
      });
  ASSERT_NO_FATAL_FAILURE(test::expect_clean_remote_session(run, port, validation));

  const test::RawDb raw(db.string());
  const std::string display = raw.value("SELECT message FROM session_events WHERE kind = 'display'");
  EXPECT_NE(display.find("answers from the controllers (left hand select 1, right hand select 2, menu 3) bound for "
                         "khr/simple_controller, valve/index_controller, htc/vive_controller, oculus/touch_controller;"),
            std::string::npos)
      << display;
  EXPECT_NE(display.find("eye gaze: none (XR_EXT_eye_gaze_interaction offered, the system has no eye tracker)"),
            std::string::npos)
      << display;

  // The instructions before trial 0 continued by a press once shown for their 4 frames.
  EXPECT_EQ(raw.value("SELECT count(*) FROM session_events WHERE kind = 'controller' AND message LIKE "
                      "'trial 0: instructions screen: controller ''%'' continued'"),
            "1");
  // Each trial answered by one press, the hand's response ("left" for the left hand, the first of
  // the demo's responses), its time from the onset to the press's stamp.
  const auto trials = raw.rows("SELECT trial_index, response, response_time_s, onset_s FROM trials ORDER BY trial_index");
  ASSERT_EQ(trials.size(), 4u);
  for (const auto& trial : trials) {
    const auto answered = raw.rows("SELECT session_time_s, message FROM session_events WHERE kind = 'controller' AND "
                                   "message LIKE 'trial " + trial[0] + ": controller %'");
    ASSERT_EQ(answered.size(), 1u) << "trial " << trial[0];
    const std::string& message = answered[0][1];
    const std::string expected_button = trial[1] == "left" ? "left hand select" : "right hand select";
    EXPECT_EQ(message, "trial " + trial[0] + ": controller '" + expected_button + "' answered '" + trial[1] + "'");
    EXPECT_NEAR(std::stod(trial[2]), std::stod(answered[0][0]) - std::stod(trial[3]), 1e-6) << message;
    EXPECT_GT(std::stod(trial[2]), 0.0) << message;
  }
  // Every logged press is one the test made, with its button; the menu never answers (two
  // alternatives: "3" is no response), though like any button it continues a screen.
  std::map<std::string, int> logged;
  for (const auto& event : raw.rows("SELECT kind, message FROM session_events WHERE kind IN ('controller', "
                                    "'ignored_controller') ORDER BY id")) {
    const std::size_t open = event[1].find("controller '");
    ASSERT_NE(open, std::string::npos) << event[1];
    const std::size_t start = open + std::strlen("controller '");
    const std::string button = event[1].substr(start, event[1].find('\'', start) - start);
    ++logged[button];
    if (button == "menu" && event[1].find(" screen: ") == std::string::npos) {
      EXPECT_EQ(event[0], "ignored_controller") << event[1];
    }
  }
  for (const auto& [button, count] : logged) EXPECT_LE(count, pressed[button]) << button;
  EXPECT_GE(logged["left hand select"] + logged["right hand select"], 4);
}

}  // namespace
}  // namespace glarelab
