// `glarelab timing-test --display window` in a real X window (under xvfb-run, tests/CMakeLists.txt):
// it completes with every frame logged on the monotonic clock and figures that hang together. No
// assertion is made on speed: Xvfb has no retrace and the machine is shared.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "cli_process.h"
#include "runner/store/result_store.h"
#include "scratch_dir.h"
#include "session_events.h"

namespace glarelab {
namespace {

TEST(WindowBackendTimingTest, TearingPatternCompletesWithEveryFrameLoggedAndTheDisplayInfoDump) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  const test::ScratchDir dir;
  const std::string db = dir.file("rig.db");
  const int frames = 90;
  const auto run = test::run_glarelab({"timing-test", "--display", "window", "--frames", std::to_string(frames),
                                       "--pattern", "tearing", "--width", "320", "--height", "200", "--db", db},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, ::testing::HasSubstr("loop overhead p50 "));

  const ResultStore store(db);
  const auto session = store.load_sessions().at(0);
  EXPECT_EQ(session.status, "completed");
  EXPECT_EQ(session.display_backend, "window");
  EXPECT_EQ(session.clock, "monotonic");
  const auto trials = store.load_trials(session.id);
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].procedure, "timing_test");
  const auto flips = store.load_frames(trials[0].id);
  ASSERT_EQ(flips.size(), static_cast<std::size_t>(frames));
  long dropped = 0;
  for (std::size_t k = 0; k < flips.size(); ++k) {
    EXPECT_EQ(flips[k].frame_index, static_cast<int>(k));
    if (k > 0) {
      EXPECT_GT(flips[k].flip_s, flips[k - 1].flip_s) << "flip stamps rise on the monotonic clock";
    }
    dropped += flips[k].dropped ? 1 : 0;
  }
  EXPECT_EQ(trials[0].onset_s, flips.front().flip_s);
  // The figures agree with the frames they came from: the reported count of missed deadlines is
  // the number of frames marked dropped.
  const auto figures = test::session_event_messages(store, "timing_test");
  ASSERT_EQ(figures.size(), 1u);
  EXPECT_THAT(figures[0], ::testing::HasSubstr(std::to_string(frames) + " frames; flip interval mean "));
  EXPECT_THAT(figures[0], ::testing::HasSubstr("missed deadlines " + std::to_string(dropped) + " "));
  const auto display = test::session_event_messages(store, "display");
  ASSERT_EQ(display.size(), 1u);
  for (const char* fact : {"backend window 320x200", "mode windowed 320x200 on monitor 0 '", ": video mode ",
                           "vsync on", "; refresh ", "; framebuffer 8/8/8 bits", "; GL renderer ",
                           "; GL version (driver) ", "; context GLFW window", "; clock monotonic"})
    EXPECT_THAT(display[0], ::testing::HasSubstr(fact));
}

}  // namespace
}  // namespace glarelab
