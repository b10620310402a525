#pragma once
// Running the glarelab binary from tests, as a user would.
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "scratch_dir.h"

extern char** environ;

namespace glarelab::test {

// A started glarelab process whose stdout and stderr go to one file. A process that could not be
// started (the binary missing, or being relinked by a build beside the test) is a failure of the
// test that started it, naming the binary and the reason; it is never signalled or waited for, so
// no other process (pid -1 means every one) is touched or reaped in its place.
class GlarelabProcess {
 public:
  // `binary`: the program to start, glarelab unless a test of this helper names another.
  GlarelabProcess(const std::vector<std::string>& arguments, const std::filesystem::path& output_file,
                  const std::string& binary = GLARELAB_BINARY) {
    std::vector<std::string> argv_storage = {binary};
    argv_storage.insert(argv_storage.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (auto& argument : argv_storage) argv.push_back(argument.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, output_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    pid_t pid = -1;
    const int error = posix_spawn(&pid, binary.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (error == 0 && pid > 0) {
      pid_ = pid;
    } else {
      start_error_ = "could not start " + binary + ": " + std::strerror(error);
      ADD_FAILURE() << start_error_;
    }
  }
  ~GlarelabProcess() {
    if (pid_ > 0 && !finished_) {
      ::kill(pid_, SIGKILL);
      wait();
    }
  }
  GlarelabProcess(const GlarelabProcess&) = delete;
  GlarelabProcess& operator=(const GlarelabProcess&) = delete;
  bool started() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }  // -1 when it did not start
  // Why the process did not start (empty when it did).
  const std::string& start_error() const { return start_error_; }
  void signal(int number) const {
    if (pid_ > 0) ::kill(pid_, number);
  }
  // CPU seconds (user and system, every thread) the running process has used so far, from
  // /proc/PID/stat; -1 when it cannot be read. With cpu_s() after wait(): the program's own work
  // between two moments, which a loaded host does not stretch as it stretches wall time.
  double cpu_so_far_s() const {
    if (pid_ <= 0) return -1.0;
    std::ifstream file("/proc/" + std::to_string(pid_) + "/stat");
    std::string stat((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    const auto name_end = stat.rfind(')');
    if (name_end == std::string::npos) return -1.0;
    std::istringstream fields(stat.substr(name_end + 1));
    std::string field;
    unsigned long long utime = 0, stime = 0;
    // After the name: state (field 3) ... utime (field 14), stime (field 15); proc(5).
    for (int number = 3; number <= 15 && (fields >> field); ++number) {
      if (number == 14) utime = std::stoull(field);
      if (number == 15) stime = std::stoull(field);
    }
    return static_cast<double>(utime + stime) / static_cast<double>(::sysconf(_SC_CLK_TCK));
  }
  // CPU seconds the process used in all, once wait() has returned (-1 before).
  double cpu_s() const { return cpu_s_; }
  // Exit code, or 128 + signal number when killed by a signal; -1 for a process that never
  // started (already a failure of the test).
  int wait() {
    if (pid_ <= 0 || finished_) return exit_code_;
    int status = 0;
    rusage usage{};
    while (::wait4(pid_, &status, 0, &usage) < 0) {
      if (errno != EINTR) {
        ADD_FAILURE() << "waitpid(" << pid_ << "): " << std::strerror(errno);
        finished_ = true;
        return exit_code_;
      }
    }
    finished_ = true;
    cpu_s_ = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
             1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    if (WIFEXITED(status)) exit_code_ = WEXITSTATUS(status);
    else if (WIFSIGNALED(status)) exit_code_ = 128 + WTERMSIG(status);
    return exit_code_;
  }

 private:
  pid_t pid_ = -1;
  bool finished_ = false;
  int exit_code_ = -1;
  double cpu_s_ = -1.0;
  std::string start_error_;
};

struct RunOutput {
  int exit_code = -1;
  std::string output;
};

inline RunOutput run_glarelab(const std::vector<std::string>& arguments, const std::filesystem::path& work_dir) {
  const auto output_file = work_dir / ("output-" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()) + ".txt");
  GlarelabProcess process(arguments, output_file);
  RunOutput result;
  if (!process.started()) {
    result.output = process.start_error();
    return result;
  }
  result.exit_code = process.wait();
  result.output = read_bytes(output_file.string());
  return result;
}

// The demo experiment copied into `dir` with some keys replaced (simple text substitution on
// whole lines starting with the key), scene paths made absolute.
inline std::filesystem::path demo_variant(const std::filesystem::path& dir,
                                          const std::vector<std::pair<std::string, std::string>>& line_replacements) {
  const std::filesystem::path examples = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples";
  std::istringstream in(read_bytes((examples / "demo.toml").string()));
  std::ostringstream out;
  std::string line;
  while (std::getline(in, line)) {
    for (const auto& [key, replacement] : line_replacements)
      if (line.rfind(key + " ", 0) == 0 || line.rfind(key + "=", 0) == 0) line = replacement;
    const auto pos = line.find("\"scenes/");
    if (pos != std::string::npos) line.replace(pos, 1, "\"" + (examples.string() + "/"));
    if (line.rfind("file = \"demo_conditions.csv\"", 0) == 0)
      line = "file = \"" + (examples / "demo_conditions.csv").string() + "\"";
    out << line << "\n";
  }
  const auto path = dir / "experiment.toml";
  write_bytes(path.string(), out.str());
  return path;
}

// Five rows of the demo's lamps without a glare column (name,scene_a,scene_b): the 100 cd/m2 lamp
// beside one 5 % to 100 % brighter, so every row takes the [glare] default mode, control (or the
// mode a variant sets): for tests about sessions rather than glare.
inline void write_demo_conditions_without_glare(const std::filesystem::path& path) {
  write_bytes(path.string(),
              "name,scene_a,scene_b\n"
              "ratio_1.05,lamp_100,lamp_105\n"
              "ratio_1.15,lamp_100,lamp_115\n"
              "ratio_1.30,lamp_100,lamp_130\n"
              "ratio_1.60,lamp_100,lamp_160\n"
              "ratio_2.00,lamp_100,lamp_200\n");
}

// A small, quick demo for glare-in-session tests: 512 x 256 px, two frames per trial, every row
// dynamic, 8 wavelength samples; `extra_glare_keys` are more [glare] lines ("backend = \"gl\"").
inline std::filesystem::path small_dynamic_demo(const std::filesystem::path& dir, const std::string& extra_glare_keys) {
  write_demo_conditions_without_glare(dir / "conditions.csv");
  return demo_variant(dir, {{"file", "file = \"" + (dir / "conditions.csv").string() + "\""},
                            {"width_px", "width_px = 512"},
                            {"height_px", "height_px = 256"},
                            {"stimulus_frames", "stimulus_frames = 2"},
                            {"mode", "mode = \"dynamic\""},
                            {"wavelength_samples", "wavelength_samples = 8\n" + extra_glare_keys}});
}

}  // namespace glarelab::test
