// A session that fails after its row exists ends as aborted with the reason, never left
// "running" (which would also shift the default participant number of every later run).
#include <gtest/gtest.h>

#include <cstdio>

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "cli_process.h"
#include "runner/store/result_store.h"
#include "session_events.h"

namespace glarelab {
namespace {

TEST(SessionFailure, AScriptShorterThanTheDesignOrWithAWrongLineIsRefusedBeforeAnythingIsWritten) {
  const test::ScratchDir scratch;
  const std::string demo = std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml";
  const auto script = scratch.path() / "answers.txt";
  const auto db = scratch.path() / "never.db";
  const auto run = [&] {
    return test::run_glarelab(
        {"run", demo, "--display", "offscreen", "--observer", "script:" + script.string(), "--db", db.string()},
        scratch.path());
  };
  test::write_bytes(script.string(), "left\nright\nleft\n");  // the demo has 34 trials
  const auto short_script = run();
  EXPECT_EQ(short_script.exit_code, 2) << short_script.output;
  EXPECT_NE(short_script.output.find(script.string() + ":4: response script holds 3 responses; trial 3 needs response 4"),
            std::string::npos)
      << short_script.output;
  EXPECT_FALSE(std::filesystem::exists(db));

  std::string answers;
  for (int k = 0; k < 34; ++k) answers += k == 11 ? "up\n" : "left\n";
  test::write_bytes(script.string(), answers);
  const auto wrong_line = run();
  EXPECT_EQ(wrong_line.exit_code, 2) << wrong_line.output;
  EXPECT_NE(wrong_line.output.find(script.string() + ":12:1: response 'up' is not allowed"), std::string::npos)
      << wrong_line.output;
  EXPECT_FALSE(std::filesystem::exists(db));

  // A script that ends in "abort" is a complete script: the session runs until that line.
  answers = "left\nright\nabort\n";
  test::write_bytes(script.string(), answers);
  const auto aborted = run();
  EXPECT_EQ(aborted.exit_code, 130) << aborted.output;
  const ResultStore store(db.string());
  EXPECT_EQ(store.load_sessions().at(0).status, "aborted");
  EXPECT_EQ(store.load_trials(store.load_sessions().at(0).id).size(), 2u);
}

TEST(SessionFailure, ResumingWithAnotherExperimentsFileIsRefused) {
  const test::ScratchDir scratch;
  const auto db = scratch.path() / "demo.db";
  const std::string examples = std::string(GLARELAB_SOURCE_DIR) + "/examples/";
  ASSERT_EQ(test::run_glarelab({"run", examples + "demo.toml", "--display", "offscreen", "--observer", "simulated",
                                "--db", db.string(), "--stop-after", "2"},
                               scratch.path())
                .exit_code,
            0);
  const auto other = test::run_glarelab({"run", examples + "luidolt_ratings.toml", "--display", "offscreen",
                                         "--observer", "simulated", "--db", db.string(), "--resume", "1"},
                                        scratch.path());
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find(examples + "luidolt_ratings.toml: key 'experiment.name': session 1 in " + db.string() +
                              " is of experiment 'demo-which-light-is-brighter', not 'luidolt-2020-ratings'"),
            std::string::npos)
      << other.output;
  const ResultStore store(db.string());
  EXPECT_EQ(store.load_sessions().at(0).status, "running");  // untouched, still resumable
  EXPECT_EQ(store.load_trials(1).size(), 2u);
}

TEST(SessionFailure, SigtermWhileGlareFramesArePreparedEndsWithinAFrameNotATrial) {
  const test::ScratchDir scratch;
  const auto& dir = scratch.path();
  // Every row dynamic glare, 120 frames per trial: preparing one trial's frames takes seconds.
  std::string rows = "name,scene_a,scene_b,glare\n";
  for (const char* scene : {"lamp_105", "lamp_115", "lamp_130"})
    rows += std::string("ratio_") + scene + ",lamp_100," + scene + ",dynamic\n";
  test::write_bytes((dir / "dynamic.csv").string(), rows);
  const auto experiment = test::demo_variant(dir, {{"file", "file = \"" + (dir / "dynamic.csv").string() + "\""},
                                                   {"stimulus_frames", "stimulus_frames = 120"}});
  const auto db = dir / "term.db";
  test::GlarelabProcess process(
      {"run", experiment.string(), "--db", db.string(), "--display", "offscreen", "--observer", "simulated"},
      dir / "out.txt");
  // The session row is written just before the first trial's frames are prepared.
  for (int i = 0; i < 2400 && !std::filesystem::exists(db); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(25));
  ASSERT_TRUE(std::filesystem::exists(db)) << test::read_bytes(dir / "out.txt");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const auto signalled = std::chrono::steady_clock::now();
  const double cpu_before_s = process.cpu_so_far_s();
  process.signal(SIGTERM);
  EXPECT_EQ(process.wait(), 130) << test::read_bytes(dir / "out.txt");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
  // What the program did after the signal, in CPU seconds: a loaded host stretches the wall time
  // from the signal to the exit (4.2 s at load 12 on two cores) but not the work. One dynamic
  // frame here is about 0.06 s on an idle 2-core machine, so the trial's 120 frames are several
  // CPU seconds; stopping at the next frame, then ending the session, took 0.42 CPU-s.
  ASSERT_GE(cpu_before_s, 0.0);
  const double cpu_after_s = process.cpu_s() - cpu_before_s;
  std::printf("[ figures  ] SIGTERM to exit: %.3f s wall, %.3f CPU-s of the program\n", seconds, cpu_after_s);
  EXPECT_LT(cpu_after_s, 2.0);

  const ResultStore store(db.string());
  const auto session = store.load_sessions().at(0);
  EXPECT_EQ(session.status, "aborted");
  EXPECT_TRUE(store.load_trials(session.id).empty());  // the trial in preparation never started
  const auto aborted = test::session_event_messages(store, "aborted");
  ASSERT_EQ(aborted.size(), 1u);
  EXPECT_EQ(aborted[0], "interrupted (Ctrl-C or SIGTERM)");
}

// A failure that can only happen mid-run (here a frame of --save-frames that cannot be written:
// its name is taken by a directory) ends the session as aborted, with the reason as its 'aborted'
// event; the trials committed before it stay, and the exit code is the error's, not 1.
TEST(SessionFailure, AFailureMidRunEndsTheSessionAbortedWithTheReasonAndKeepsItsTrials) {
  const test::ScratchDir scratch;
  const auto db = scratch.path() / "failed.db";
  const auto frames = scratch.path() / "frames";
  std::filesystem::create_directories(frames / "trial_0002.exr");
  const std::string demo = std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml";
  const auto run = test::run_glarelab({"run", demo, "--display", "offscreen", "--observer", "simulated", "--db",
                                       db.string(), "--save-frames", frames.string()},
                                      scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("trial_0002.exr"), std::string::npos) << run.output;
  const ResultStore store(db.string());
  const auto session = store.load_sessions().at(0);
  EXPECT_EQ(session.status, "aborted");
  EXPECT_EQ(store.load_trials(session.id).size(), 2u);
  const auto aborted = test::session_event_messages(store, "aborted");
  ASSERT_EQ(aborted.size(), 1u);
  EXPECT_EQ(aborted[0].rfind("failed: ", 0), 0u) << aborted[0];
  EXPECT_NE(aborted[0].find("trial_0002.exr"), std::string::npos) << aborted[0];
}

TEST(SessionFailure, TwoRunsStartedTogetherOnOneDatabaseGetDistinctParticipantNumbers) {
  const test::ScratchDir scratch;
  const auto db = scratch.path() / "shared.db";
  const std::string demo = std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml";
  // Both count the sessions before either writes its row (opening a display takes far longer
  // than starting a process), so both count 0.
  test::GlarelabProcess first({"run", demo, "--display", "offscreen", "--observer", "simulated", "--db", db.string(),
                               "--stop-after", "1"},
                              scratch.path() / "first.txt");
  test::GlarelabProcess second({"run", demo, "--display", "offscreen", "--observer", "simulated", "--db", db.string(),
                                "--stop-after", "1"},
                               scratch.path() / "second.txt");
  EXPECT_EQ(first.wait(), 0) << test::read_bytes(scratch.path() / "first.txt");
  EXPECT_EQ(second.wait(), 0) << test::read_bytes(scratch.path() / "second.txt");
  const ResultStore store(db.string());
  ASSERT_EQ(store.load_sessions().size(), 2u);
  std::vector<std::string> numbers = test::session_event_messages(store, "participant_number");
  ASSERT_EQ(numbers.size(), 2u);
  std::sort(numbers.begin(), numbers.end());
  EXPECT_EQ(numbers[0].rfind("1 (1 + 0 earlier session(s)", 0), 0u) << numbers[0];
  EXPECT_EQ(numbers[1].rfind("2 (1 + 1 earlier session(s)", 0), 0u) << numbers[1];
}

}  // namespace
}  // namespace glarelab
