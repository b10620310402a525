// Progress (issue: a lab's first study): glarelab run on a terminal keeps a status line (trial k of
// n, elapsed, time left) that appears within 2 s of the start and is redrawn at least every 2 s;
// piped, stdout is line-buffered and the run's lines arrive as they are written, the first before
// the first trial, with plain progress lines between.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include "cli_process.h"
#include "runner/session/status_line.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

using Clock = std::chrono::steady_clock;

struct Chunk {
  double at_s = 0.0;  // since the process was started
  std::string text;
};

// Reads `fd` until end of file (a pty's master reads EIO once the child has gone), stamping each read.
std::vector<Chunk> read_stamped(int fd, Clock::time_point start, double limit_s) {
  std::vector<Chunk> chunks;
  char buffer[4096];
  while (std::chrono::duration<double>(Clock::now() - start).count() < limit_s) {
    pollfd ready{fd, POLLIN, 0};
    if (::poll(&ready, 1, 200) <= 0) continue;
    const ssize_t got = ::read(fd, buffer, sizeof buffer);
    if (got <= 0) break;
    chunks.push_back({std::chrono::duration<double>(Clock::now() - start).count(), std::string(buffer, static_cast<std::size_t>(got))});
  }
  return chunks;
}

std::vector<std::string> run_arguments(const std::filesystem::path& experiment, const std::filesystem::path& db) {
  // --clock real: the offscreen run is paced by the wall clock, so it lasts as a window's would.
  return {GLARELAB_BINARY, "run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
          "--clock", "real", "--db", db.string(), "--stop-after", "8"};
}

TEST(RunProgress, OnATerminalTheStatusLineComesWithinTwoSecondsAndEveryTwoSeconds) {
  const test::ScratchDir dir;
  const auto experiment = test::demo_variant(dir.path(), {});
  std::vector<std::string> arguments = run_arguments(experiment, dir.path() / "tty.db");
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  int master = -1;
  const Clock::time_point start = Clock::now();
  const pid_t pid = ::forkpty(&master, nullptr, nullptr, nullptr);
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execv(GLARELAB_BINARY, argv.data());
    ::_exit(127);
  }
  const std::vector<Chunk> chunks = read_stamped(master, start, 120.0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ::close(master);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  std::vector<double> drawn_s;  // each redraw of the status line: an erase, then "... elapsed"
  std::string all;
  for (const Chunk& chunk : chunks) {
    all += chunk.text;
    for (std::size_t at = chunk.text.find("\r\033[K"); at != std::string::npos; at = chunk.text.find("\r\033[K", at + 1))
      if (chunk.text.find(" elapsed", at) != std::string::npos) drawn_s.push_back(chunk.at_s);
  }
  ASSERT_FALSE(drawn_s.empty()) << all;
  const double end_s = chunks.back().at_s;
  std::printf("status line drawn %zu times over %.2f s, first at %.2f s\n", drawn_s.size(), end_s, drawn_s.front());
  EXPECT_LE(drawn_s.front(), 2.0);
  double longest_gap_s = 0.0;
  for (std::size_t i = 1; i < drawn_s.size(); ++i) longest_gap_s = std::max(longest_gap_s, drawn_s[i] - drawn_s[i - 1]);
  longest_gap_s = std::max(longest_gap_s, end_s - drawn_s.back());
  std::printf("longest gap between redraws %.2f s\n", longest_gap_s);
  EXPECT_LE(longest_gap_s, 2.0);
  EXPECT_GE(end_s, 3.0) << "the run should last long enough for the redraws to matter";
  EXPECT_NE(all.find("trial 8 of 34"), std::string::npos) << all;
  EXPECT_NE(all.find(" left"), std::string::npos) << all;  // the time left, once a trial has passed
  EXPECT_NE(all.find("Session 1 of"), std::string::npos) << all;
}

TEST(RunProgress, PipedTheFirstLineArrivesBeforeTheFirstTrialAndPlainLinesFollow) {
  const test::ScratchDir dir;
  const auto experiment = test::demo_variant(dir.path(), {});
  std::vector<std::string> arguments = run_arguments(experiment, dir.path() / "piped.db");
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 1);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  pid_t pid = -1;
  const Clock::time_point start = Clock::now();
  ASSERT_EQ(posix_spawn(&pid, GLARELAB_BINARY, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[1]);
  const std::vector<Chunk> chunks = read_stamped(pipe_fds[0], start, 120.0);
  ::close(pipe_fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  ASSERT_FALSE(chunks.empty());
  std::string all;
  double session_line_s = -1.0, second_trial_line_s = -1.0;
  for (const Chunk& chunk : chunks) {
    all += chunk.text;
    if (session_line_s < 0.0 && all.find("Session 1 of") != std::string::npos) session_line_s = chunk.at_s;
    if (second_trial_line_s < 0.0 && all.find("  trial ") != std::string::npos &&
        all.find("  trial ", all.find("  trial ") + 1) != std::string::npos)
      second_trial_line_s = chunk.at_s;
  }
  EXPECT_EQ(all.find("\033["), std::string::npos) << "no terminal controls in a pipe";
  const double end_s = chunks.back().at_s;
  std::printf("piped: session line at %.2f s, second progress line at %.2f s, end %.2f s\n", session_line_s,
              second_trial_line_s, end_s);
  // The session line is written before the first trial; line-buffered, it arrives then, not at the end.
  ASSERT_GE(session_line_s, 0.0) << all;
  EXPECT_LT(session_line_s, end_s - 1.5) << all;
  // A later plain progress line arrives while the run goes on, before the end.
  ASSERT_GE(second_trial_line_s, 0.0) << all;
  EXPECT_GT(second_trial_line_s, session_line_s + 1.0);
  EXPECT_LT(second_trial_line_s, end_s);
}

}  // namespace
}  // namespace glarelab
