// glarelab: psychophysics experiment runner and stimulus presenter for glare studies.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "runner/cli/commands.h"
#include "runner/cli/terminal_stream.h"
#include "core/frame_allocation.h"
#include "core/software_version.h"

int main(int argc, char** argv) {
  glarelab::keep_freed_frames_in_the_process();  // core/frame_allocation.h
  // Line-buffered stdout even into a pipe or a file: a long run's lines arrive as they are
  // written, not in one block at the end (std::cout writes through stdio, synchronised).
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  // Everything printed from here on has its control characters escaped (runner/cli/terminal_stream.h).
  static glarelab::cli::TerminalTextGuard terminal_text;
  CLI::App app{"glarelab: psychophysics experiments with HDR stimuli and glare"};
  app.set_version_flag("--version", std::string("glarelab ") + glarelab::software_version());
  app.require_subcommand(1);
  // Each subcommand registers its options and hands back what to run once parsing succeeded.
  const std::vector<std::pair<std::string, glarelab::cli::Action>> commands = {
      {"run", glarelab::cli::add_run_command(app)},
      {"validate", glarelab::cli::add_validate_command(app)},
      {"psf", glarelab::cli::add_psf_command(app)},
      {"eye-trace", glarelab::cli::add_eye_trace_command(app)},
      {"analyze", glarelab::cli::add_analyze_command(app)},
      {"devices", glarelab::cli::add_devices_command(app)},
      {"bench", glarelab::cli::add_bench_command(app)},
      {"render", glarelab::cli::add_render_command(app)},
      {"calibrate", glarelab::cli::add_calibrate_command(app)},
      {"timing-test", glarelab::cli::add_timing_test_command(app)},
      {"fit", glarelab::cli::add_fit_command(app)},
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // Usage errors are bad input (exit 2), like a broken experiment file.
    const int code = app.exit(error);
    return code == 0 ? 0 : 2;
  }
  for (const auto& [name, action] : commands)
    if (app.got_subcommand(name)) return action();
  return 2;
}
