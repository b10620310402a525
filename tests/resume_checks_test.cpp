// What a resume checks before it goes on (docs/DATABASE.md "sessions" and "session_events"): the
// session's clock, so that its onsets stay one time line, and its scene files, so that the trials
// still to come show what the first ones showed. Each is run as a user would.
#include <gtest/gtest.h>

#include <filesystem>
#include <tuple>
#include <string>
#include <vector>

#include "cli_process.h"
#include "raw_db.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

using test::read_bytes;
using test::run_glarelab;
using test::write_bytes;

// Ten trials of the demo's lamps without glare, small and short.
std::string short_session(const std::filesystem::path& dir) {
  test::write_demo_conditions_without_glare(dir / "conditions.csv");
  return test::demo_variant(dir, {{"file", "file = \"" + (dir / "conditions.csv").string() + "\""},
                                  {"question", "question = \"\""},
                                  {"stimulus_frames", "stimulus_frames = 4"},
                                  {"width_px", "width_px = 256"},
                                  {"height_px", "height_px = 128"}})
      .string();
}

std::vector<std::string> run_args(const std::string& experiment, const std::filesystem::path& db,
                                  std::vector<std::string> extra) {
  std::vector<std::string> all = {"run", experiment, "--db", db.string(), "--display", "offscreen", "--observer",
                                  "simulated"};
  all.insert(all.end(), extra.begin(), extra.end());
  return all;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(ResumeChecks, ASessionResumesOnTheClockItBeganOnAndAnotherClockIsRefused) {
  const test::ScratchDir scratch;
  const auto& dir = scratch.path();
  const std::string experiment = short_session(dir);
  for (const auto& [began_on, stored, other] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"real", "monotonic", "virtual"}, {"virtual", "virtual", "real"}}) {
    const auto db = dir / (began_on + ".db");
    const auto stopped = run_glarelab(run_args(experiment, db, {"--clock", began_on, "--stop-after", "4"}), dir);
    ASSERT_EQ(stopped.exit_code, 0) << stopped.output;
    // Another clock: refused at --clock, nothing written.
    const auto refused = run_glarelab(run_args(experiment, db, {"--resume", "1", "--clock", other}), dir);
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_TRUE(contains(refused.output, "--clock")) << refused.output;
    EXPECT_TRUE(contains(refused.output, "ran on the " + stored + " clock")) << refused.output;
    EXPECT_EQ(test::RawDb(db.string()).value("SELECT count(*) FROM session_events WHERE kind = 'resumed'"), "0");
    // No --clock: the stored one, and the time line goes on.
    const auto resumed = run_glarelab(run_args(experiment, db, {"--resume", "1"}), dir);
    ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
    const test::RawDb store(db.string());
    EXPECT_EQ(store.value("SELECT status || ' ' || clock FROM sessions WHERE id = 1"), "completed " + stored);
    EXPECT_TRUE(contains(store.value("SELECT message FROM session_events WHERE kind = 'resumed'"), stored + " clock"));
    EXPECT_EQ(store.value("SELECT count(*) FROM trials"), "10");
    // Every flip after the one before it, across the resume: one clock, one time line.
    const auto flips = store.rows("SELECT flip_s FROM frames ORDER BY rowid");
    ASSERT_GE(flips.size(), 40u);
    for (std::size_t i = 1; i < flips.size(); ++i)
      ASSERT_GT(std::stod(flips[i][0]), std::stod(flips[i - 1][0])) << began_on << ": flip " << i;
  }
  // A session of the virtual clock cannot go on in a window, whose clock is real.
  const auto windowed =
      run_glarelab({"run", experiment, "--db", (dir / "virtual-again.db").string(), "--display", "offscreen",
                    "--observer", "simulated", "--stop-after", "2"},
                   dir);
  ASSERT_EQ(windowed.exit_code, 0) << windowed.output;
  const auto in_window = run_glarelab({"run", experiment, "--db", (dir / "virtual-again.db").string(), "--display",
                                       "window", "--observer", "simulated", "--resume", "1"},
                                      dir);
  EXPECT_EQ(in_window.exit_code, 2) << in_window.output;
  EXPECT_TRUE(contains(in_window.output, "--display")) << in_window.output;
}

TEST(ResumeChecks, ASceneFileChangedOrGoneSinceTheRunIsRefusedAtItsKeyAndRestoredItResumes) {
  const test::ScratchDir scratch;
  const auto& dir = scratch.path();
  // The scenes copied beside the experiment, so that the test can change one.
  const std::filesystem::path examples = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples";
  std::filesystem::create_directories(dir / "scenes");
  for (const auto& entry : std::filesystem::directory_iterator(examples / "scenes"))
    std::filesystem::copy_file(entry.path(), dir / "scenes" / entry.path().filename());
  std::string text = read_bytes(short_session(dir));
  for (std::size_t at; (at = text.find((examples / "scenes").string())) != std::string::npos;)
    text.replace(at, (examples / "scenes").string().size(), (dir / "scenes").string());
  write_bytes((dir / "experiment.toml").string(), text);
  const std::string experiment = (dir / "experiment.toml").string();
  const auto db = dir / "results.db";
  const auto stopped = run_glarelab(run_args(experiment, db, {"--stop-after", "3"}), dir);
  ASSERT_EQ(stopped.exit_code, 0) << stopped.output;

  // The session's fingerprints: one line per scene file, with the file's size.
  const std::string fingerprints =
      test::RawDb(db.string()).value("SELECT message FROM session_events WHERE kind = 'scene_fingerprint'");
  const auto lamp = dir / "scenes" / "lamp_130.exr";
  EXPECT_TRUE(contains(fingerprints, "lamp_130\tfnv1a64=")) << fingerprints;
  EXPECT_TRUE(contains(fingerprints, " bytes=" + std::to_string(std::filesystem::file_size(lamp)) + "\t" +
                                         lamp.string() + "\n"))
      << fingerprints;

  const std::string original = read_bytes(lamp.string());
  std::string changed = original;
  changed[changed.size() / 2] = static_cast<char>(changed[changed.size() / 2] ^ 0x01);  // one bit of one pixel
  write_bytes(lamp.string(), changed);
  const auto refused = run_glarelab(run_args(experiment, db, {"--resume", "1"}), dir);
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_TRUE(contains(refused.output, experiment + ":")) << refused.output;
  EXPECT_TRUE(contains(refused.output, "scenes.lamp_130")) << refused.output;
  EXPECT_TRUE(contains(refused.output, "changed since session 1 started")) << refused.output;

  std::filesystem::remove(lamp);
  const auto gone = run_glarelab(run_args(experiment, db, {"--resume", "1"}), dir);
  EXPECT_EQ(gone.exit_code, 2) << gone.output;
  EXPECT_TRUE(contains(gone.output, "is gone since session 1 started")) << gone.output;
  EXPECT_EQ(test::RawDb(db.string()).value("SELECT count(*) FROM trials"), "3");

  write_bytes(lamp.string(), original);
  const auto resumed = run_glarelab(run_args(experiment, db, {"--resume", "1"}), dir);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(test::RawDb(db.string()).value("SELECT status FROM sessions"), "completed");
  EXPECT_EQ(test::RawDb(db.string()).value("SELECT count(*) FROM trials"), "10");
}

}  // namespace
}  // namespace glarelab
