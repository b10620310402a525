#pragma once
// Each subcommand registers its options on the CLI11 app and returns the action to run after
// parsing. Only subcommands that work are registered.
#include <CLI/CLI.hpp>

#include <functional>

namespace glarelab::cli {

using Action = std::function<int()>;

Action add_run_command(CLI::App& app);
Action add_validate_command(CLI::App& app);
Action add_psf_command(CLI::App& app);
Action add_analyze_command(CLI::App& app);
Action add_eye_trace_command(CLI::App& app);
Action add_devices_command(CLI::App& app);
Action add_bench_command(CLI::App& app);
Action add_render_command(CLI::App& app);
Action add_calibrate_command(CLI::App& app);
Action add_timing_test_command(CLI::App& app);
Action add_fit_command(CLI::App& app);

// Runs `body`, turning glarelab's error types into a message on stderr and the documented exit code.
int report_errors(const std::function<int()>& body);

}  // namespace glarelab::cli
