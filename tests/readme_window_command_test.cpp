// The README's window command, exactly as a new user types it (from the source root, so the demo's
// default database lands in results/): `build/glarelab run examples/demo.toml --display window
// --participant P01`, under Xvfb, answered with the arrow keys and ended with Escape. The demo's
// glare conditions run with `[glare] backend = "auto"`, which opens an offscreen context to look at
// the renderer while the window's context is current; that once broke the window's context.
#include <gtest/gtest.h>

#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "cli_process.h"
#include "window_focus.h"
#include "runner/store/result_store.h"
#include "scratch_dir.h"
#include "session_events.h"

extern char** environ;

namespace glarelab {
namespace {

int shell(const std::string& command) { return std::system(command.c_str()); }

// Trials committed so far, read with the sqlite3 shell (a second reader; WAL lets it read while
// the session writes). -1 while the database does not exist yet.
int committed_trials(const std::filesystem::path& db) {
  if (!std::filesystem::exists(db)) return -1;
  const std::string command = "sqlite3 '" + db.string() + "' 'SELECT count(*) FROM trials' 2>/dev/null";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return -1;
  int count = -1;
  if (std::fscanf(pipe, "%d", &count) != 1) count = -1;
  ::pclose(pipe);
  return count;
}

bool wait_for_trials(const std::filesystem::path& db, int trials, std::chrono::seconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (committed_trials(db) >= trials) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return false;
}

TEST(WindowBackend, ReadmeWindowCommandRunsTheDemoWithGlareAndEndsCleanlyOnEscape) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  ASSERT_EQ(shell("command -v xdotool > /dev/null && command -v sqlite3 > /dev/null"), 0)
      << "xdotool and sqlite3 are needed (scripts/setup.sh installs them)";
  const test::ScratchDir scratch;
  // The source tree's layout in the scratch directory: build/glarelab and examples/, so the
  // command runs word for word and results/ is written there, not into the checkout.
  std::filesystem::create_directories(scratch.path() / "build");
  std::filesystem::create_symlink(GLARELAB_BINARY, scratch.path() / "build" / "glarelab");
  std::filesystem::create_directory_symlink(std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples",
                                            scratch.path() / "examples");
  const auto output = scratch.path() / "out.txt";
  const std::string command = "cd '" + scratch.path().string() +
                              "' && exec build/glarelab run examples/demo.toml --display window --participant P01 > '" +
                              output.string() + "' 2>&1";
  std::vector<std::string> argv_storage = {"/bin/sh", "-c", command};
  std::vector<char*> argv;
  for (auto& argument : argv_storage) argv.push_back(argument.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  ASSERT_EQ(posix_spawn(&pid, "/bin/sh", nullptr, nullptr, argv.data(), environ), 0);

  ASSERT_EQ(shell(test::focus_window_command("glarelab: demo-which-light-is-brighter", 30)),
            0)
      << test::read_bytes(output.string());
  const auto db = scratch.path() / "results" / "demo-which-light-is-brighter.db";
  // Four answers (the demo crosses three glare modes with the luminance ratios, in a seeded order).
  for (int answered = 0; answered < 4; ++answered) {
    std::this_thread::sleep_for(std::chrono::milliseconds(900));  // past the 0.5 s stimulus
    ASSERT_EQ(shell(answered % 2 == 0 ? "xdotool key Left" : "xdotool key Right"), 0);
    ASSERT_TRUE(wait_for_trials(db, answered + 1, std::chrono::seconds(60)))
        << "trial " << answered << " was not committed\n"
        << test::read_bytes(output.string());
  }
  ASSERT_EQ(shell("xdotool key Escape"), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  const std::string printed = test::read_bytes(output.string());
  ASSERT_TRUE(WIFEXITED(status)) << printed;
  EXPECT_EQ(WEXITSTATUS(status), 130) << printed;  // Escape: the session is kept as aborted
  EXPECT_EQ(printed.find("error:"), std::string::npos) << printed;

  const ResultStore store(db.string());
  const auto sessions = store.load_sessions();
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].status, "aborted");
  EXPECT_EQ(sessions[0].participant, "P01");
  EXPECT_EQ(sessions[0].display_backend, "window");
  EXPECT_GE(store.load_trials(sessions[0].id).size(), 4u);
  const std::vector<std::string> backend = test::session_event_messages(store, "glare_backend");
  ASSERT_EQ(backend.size(), 1u);
  EXPECT_NE(backend[0].find("glare backend auto picked"), std::string::npos) << backend[0];
}

}  // namespace
}  // namespace glarelab
