// Glare in a session with the GL backend: the backend works in an OpenGL context of its own, so the
// session must make the display's context current again after every trial's glare; a frame drawn in
// the wrong context would fail on the scene textures (GL errors end the run with exit code 3).
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <string>

#include "cli_process.h"
#include "runner/store/result_store.h"
#include "scratch_dir.h"
#include "session_events.h"

namespace glarelab {
namespace {

std::string first_event(const std::string& db, const std::string& kind) {
  const std::vector<std::string> messages = test::session_event_messages(db, kind);
  return messages.empty() ? std::string() : messages.front();
}

TEST(GlareSession, GlBackendRunsTrialsBetweenDisplayFrames) {
  test::ScratchDir dir;
  const auto experiment = test::small_dynamic_demo(dir.path(), "backend = \"gl\"");
  const std::string db = (dir.path() / "gl.db").string();
  const auto run = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                       "--db", db, "--seed", "3", "--stop-after", "3"},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(first_event(db, "glare_backend").find("glare backend gl: asked for by name"), std::string::npos)
      << first_event(db, "glare_backend");
  const ResultStore store(db);
  EXPECT_EQ(store.load_trials(store.load_sessions().at(0).id).size(), 3u);
}

}  // namespace
}  // namespace glarelab
