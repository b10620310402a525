// glarelab bench, memory rows (runner/cli/bench_memory.h): a child process per row, its peak
// resident size from wait4 (ru_maxrss) beside the VmHWM it read from /proc/self/status itself.
#include "runner/cli/bench_memory.h"

#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "runner/session/glared_region.h"
#include "runner/session/session_runner.h"
#include "runner/store/result_store.h"
#include "runner/store/session_summary.h"

extern char** environ;

namespace glarelab::cli {
namespace {

// The display's geometry in the generated file (the demo's: 0.024 degrees per pixel at 60 cm).
constexpr double kViewingDistanceMm = 600.0;
constexpr double kPixelPitchMm = 0.25;

long status_kib(const std::string& key) {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind(key + ":", 0) == 0) return std::stol(line.substr(key.size() + 1));  // "VmHWM:  123 kB"
  return -1;
}

SessionMemoryRow run_child(const SessionMemoryOptions& options, const std::filesystem::path& directory,
                           const std::string& glare) {
  SessionMemoryRow row;
  row.glare = glare;
  row.scene_px = memory_scene_px(options);
  if (glare == "dynamic")
    row.frame_store_bound_bytes = prepared_frames_bound_bytes(options.width_px, options.height_px, options.stimulus_frames);
  const std::filesystem::path conditions = directory / (glare + "_conditions.csv");
  const std::filesystem::path experiment = directory / (glare + ".toml");
  std::ofstream(conditions) << "name,scene_a,scene_b,glare\nlamps," << "lamp_a,lamp_b," << glare << "\n";
  std::ofstream(experiment) << memory_experiment_toml(options, row.scene_px, conditions.filename().string());

  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) throw std::runtime_error("bench memory: cannot make a pipe to the child");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 1);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  std::vector<std::string> arguments = {options.executable, "bench", "--memory-child", experiment.string()};
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, options.executable.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(pipe_fds[1]);
  if (spawned != 0) {
    close(pipe_fds[0]);
    throw std::runtime_error("bench memory: cannot start " + options.executable);
  }
  std::string output;
  char buffer[4096];
  for (ssize_t n; (n = read(pipe_fds[0], buffer, sizeof buffer)) != 0;)
    if (n > 0) output.append(buffer, static_cast<std::size_t>(n));
    else if (errno != EINTR) break;
  close(pipe_fds[0]);
  int status = 0;
  rusage usage{};
  while (wait4(pid, &status, 0, &usage) < 0)
    if (errno != EINTR) throw std::runtime_error("bench memory: lost the child process");
  row.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("bench memory: the " + glare + " session's child failed (status " + std::to_string(status) +
                             "); its messages are above");
  row.peak_rss_kib = usage.ru_maxrss;  // Linux: kilobytes (getrusage(2))
  std::istringstream lines(output);
  for (std::string key; lines >> key;) {
    if (key == "VmHWM_kib") lines >> row.vm_hwm_kib;
    else if (key == "frames_shown") lines >> row.frames_shown;
  }
  return row;
}

std::string megabytes(double bytes) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(0) << bytes / 1e6 << " MB";
  return text.str();
}

}  // namespace

int memory_scene_px(const SessionMemoryOptions& options) {
  // Each scene nearly fills its half of the display: glare then changes almost the whole frame.
  return std::max(16, static_cast<int>(0.98 * std::min(options.width_px / 2, options.height_px)));
}

std::string memory_experiment_toml(const SessionMemoryOptions& options, int scene_px, const std::string& conditions_file) {
  // The bulb 5 % of the scene's side (desk_lamp allows 15 %), in degrees at the display's geometry.
  const double bulb_mm = 0.05 * scene_px * kPixelPitchMm;
  const double bulb_deg = 2.0 * std::atan(bulb_mm / 2.0 / kViewingDistanceMm) * 180.0 / std::numbers::pi;
  std::ostringstream toml;
  toml << std::setprecision(17);
  toml << "[experiment]\nname = \"bench-memory\"\nseed = 12\n\n"
       << "[display]\nwidth_px = " << options.width_px << "\nheight_px = " << options.height_px
       << "\nrefresh_hz = 60.0\nviewing_distance_mm = " << kViewingDistanceMm << "\npixel_pitch_mm = " << kPixelPitchMm
       << "\npeak_luminance_cd_m2 = 250.0\nbackground_cd_m2 = 0.0\nencoding = \"srgb\"\n\n"
       << "[scenes]\n"
       << "lamp_a = { generator = \"desk_lamp\", size_px = " << scene_px << ", disc_diameter_deg = " << bulb_deg
       << ", disc_fraction_of_peak = 0.5 }\n"
       << "lamp_b = { generator = \"desk_lamp\", size_px = " << scene_px << ", disc_diameter_deg = " << bulb_deg
       << ", disc_fraction_of_peak = 0.75 }\n\n"
       << "[procedure]\ntype = \"forced_choice\"\nalternatives = 2\nlayout = \"side_by_side\"\n"
       << "question = \"Which light is brighter?\"\nstimulus_frames = " << options.stimulus_frames
       << "\nrepetitions = 1\ncounterbalance_sides = true\nresponses = [\"left\", \"right\"]\n\n"
       << "[conditions]\nfile = \"" << conditions_file << "\"\n\n"
       << "[observer.simulated]\nthreshold_log10 = 0.05\nslope = 3.5\nlapse = 0.02\n\n"
       // The demo's glare (examples/demo.toml), its frames prepared before onset whatever they cost.
       << "[glare]\nmode = \"control\"\ngrid_px = 256\naperture_width_mm = 10.0\nwavelength_samples = 16\n"
       << "presentation = \"prepared\"\n";
  return toml.str();
}

std::vector<SessionMemoryRow> measure_session_memory(const SessionMemoryOptions& options) {
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("glarelab-bench-memory-" + std::to_string(getpid()));
  std::filesystem::create_directories(directory);
  std::vector<SessionMemoryRow> rows;
  try {
    for (const std::string glare : {"control", "dynamic"}) rows.push_back(run_child(options, directory, glare));
  } catch (...) {
    std::filesystem::remove_all(directory);
    throw;
  }
  std::filesystem::remove_all(directory);
  return rows;
}

std::string format_session_memory(const SessionMemoryOptions& options, const std::vector<SessionMemoryRow>& rows) {
  std::ostringstream text;
  text << "Memory: peak resident set size of one trial of a " << options.width_px << " x " << options.height_px
       << " offscreen session (simulated observer, 2-AFC of two desk lamps side by side, each "
       << (rows.empty() ? 0 : rows.front().scene_px) << " px square, " << options.stimulus_frames
       << " stimulus frames, the demo's glare: grid 256, 16 wavelengths), each in a child process: ru_maxrss from "
          "wait4 and the child's own VmHWM (/proc/self/status) after its trial. Dynamic frames are prepared before "
          "onset; the store bound is the most their changed rectangles can take (frame 0 float32 RGBA, the others "
          "half-float RGB).\n\n"
       << "| glare | stimulus frames shown | peak resident (ru_maxrss) | VmHWM | prepared-frame store at most | wall s |\n"
       << "|---|---|---|---|---|---|\n";
  for (const SessionMemoryRow& row : rows)
    text << "| " << row.glare << " | " << row.frames_shown << " | " << megabytes(1024.0 * static_cast<double>(row.peak_rss_kib)) << " | "
         << megabytes(1024.0 * static_cast<double>(row.vm_hwm_kib)) << " | "
         << (row.frame_store_bound_bytes > 0 ? megabytes(static_cast<double>(row.frame_store_bound_bytes)) : "none")
         << " | " << std::fixed << std::setprecision(1) << row.wall_s << std::defaultfloat << " |\n";
  return text.str();
}

int run_memory_child(const std::string& experiment_path, std::ostream& out) {
  RunOptions run;
  run.experiment_path = experiment_path;
  run.display = "offscreen";
  run.observer = "simulated";
  run.db_path = std::filesystem::path(experiment_path).replace_extension(".db").string();
  run.stop_after_trials = 1;
  std::ostringstream progress;
  const RunResult result = run_session(run, progress);
  // Stimulus frames as the database holds them (a run stopped after its trial reports none itself).
  const std::int64_t frames = summarise_session(ResultStore(result.db_path), result.session_id).frames;
  out << "frames_shown " << frames << "\nVmHWM_kib " << status_kib("VmHWM") << "\n" << std::flush;
  return 0;
}

}  // namespace glarelab::cli
