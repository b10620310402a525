#pragma once
// glarelab bench, memory rows: the peak resident set size of a session's glare trial at display
// size (default 1920 x 1080), measured in a child process so that nothing the bench itself holds
// counts. The child is this executable (`bench --memory-child FILE`, a hidden option) running one
// trial of a generated experiment offscreen with the simulated observer: two desk lamps
// (stimuli/spencer_scenes.h) side by side, each nearly filling its half of the display, so glare
// changes almost the whole frame (the worst case of a prepared trial's frame store,
// runner/session/glared_region.h). One row per glare mode: control (the session without glare) and
// dynamic with its frames prepared before onset (one per stimulus frame).
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace glarelab::cli {

struct SessionMemoryOptions {
  int width_px = 1920;
  int height_px = 1080;
  int stimulus_frames = 30;
  std::string executable = "/proc/self/exe";  // run as the child
};

struct SessionMemoryRow {
  std::string glare;  // "control" or "dynamic"
  int scene_px = 0;   // side of each square scene
  // The child's peak resident set size as its parent sees it (wait4's ru_maxrss, KiB) and as the
  // child read it from /proc/self/status (VmHWM, KiB) after its trial, just before exiting.
  // ru_maxrss is the larger of the two when the parent had grown first: Linux's exec records the
  // high-water mark of the address space it replaces, and posix_spawn's child shares the parent's
  // until exec (CLONE_VM), so the rows are measured from a process that has not grown yet.
  long peak_rss_kib = 0;
  long vm_hwm_kib = 0;
  long frames_shown = 0;  // stimulus frames the child's trial flipped
  // At most the bytes of the trial's prepared frames (runner/session/glared_region.h); 0 for
  // control, which prepares none.
  std::size_t frame_store_bound_bytes = 0;
  double wall_s = 0.0;
};

// Writes the experiment into a temporary directory, runs a child per row and removes the
// directory. Throws std::runtime_error ("bench memory: ...") when a child fails.
std::vector<SessionMemoryRow> measure_session_memory(const SessionMemoryOptions& options);
std::string format_session_memory(const SessionMemoryOptions& options, const std::vector<SessionMemoryRow>& rows);

// The child's side: runs one trial of `experiment_path` offscreen (database beside it) and
// writes "frames_shown N" and "VmHWM_kib N" lines to `out`. Returns the exit code.
int run_memory_child(const std::string& experiment_path, std::ostream& out);

// The generated experiment (TOML) and its conditions table for `glare` ("control" or "dynamic").
std::string memory_experiment_toml(const SessionMemoryOptions& options, int scene_px, const std::string& conditions_file);
int memory_scene_px(const SessionMemoryOptions& options);

}  // namespace glarelab::cli
