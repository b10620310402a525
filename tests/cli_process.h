#pragma once
// Running the glarelab binary from tests, as a user would.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "scratch_dir.h"

extern char** environ;

namespace glarelab::test {

// A started glarelab process whose stdout and stderr go to one file.
class GlarelabProcess {
 public:
  GlarelabProcess(const std::vector<std::string>& arguments, const std::filesystem::path& output_file) {
    std::vector<std::string> argv_storage = {GLARELAB_BINARY};
    argv_storage.insert(argv_storage.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (auto& argument : argv_storage) argv.push_back(argument.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, output_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    if (posix_spawn(&pid_, GLARELAB_BINARY, &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  ~GlarelabProcess() {
    if (pid_ > 0 && !finished_) {
      ::kill(pid_, SIGKILL);
      wait();
    }
  }
  bool started() const { return pid_ > 0; }
  void signal(int number) const { ::kill(pid_, number); }
  // Exit code, or 128 + signal number when killed by a signal.
  int wait() {
    int status = 0;
    ::waitpid(pid_, &status, 0);
    finished_ = true;
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return -1;
  }

 private:
  pid_t pid_ = -1;
  bool finished_ = false;
};

struct RunOutput {
  int exit_code = -1;
  std::string output;
};

inline RunOutput run_glarelab(const std::vector<std::string>& arguments, const std::filesystem::path& work_dir) {
  const auto output_file = work_dir / ("output-" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()) + ".txt");
  GlarelabProcess process(arguments, output_file);
  RunOutput result;
  if (!process.started()) return result;
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
