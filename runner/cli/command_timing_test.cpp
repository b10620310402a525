// glarelab timing-test: flips --frames frames of a flicker (photodiode) or tearing (eye) pattern and
// reports the flip intervals, missed deadlines, present call and loop overhead, written as a session
// to --db so `glarelab analyze` shows it (docs/TIMING.md).
#include <iostream>
#include <memory>

#include "core/errors.h"
#include "runner/cli/commands.h"
#include "runner/cli/display_options.h"
#include "runner/cli/option_checks.h"
#include "runner/timing/timing_test_run.h"

namespace glarelab::cli {

Action add_timing_test_command(CLI::App& app) {
  auto options = std::make_shared<TimingTestOptions>();
  auto display = std::make_shared<DisplayOptions>();
  auto pattern = std::make_shared<std::string>("flicker");
  CLI::App* command = app.add_subcommand(
      "timing-test", "Flip frames of a flicker or tearing pattern and measure the flip intervals, missed deadlines, "
                     "present call and loop overhead (after Psychtoolbox's VBLSyncTest); written as a session");
  add_display_options(command, *display, "window");
  command->add_option("--frames", options->frames, "Frames to flip")
      ->check(whole_number_check(2, 1000000))
      ->capture_default_str();
  command->add_option("--pattern", *pattern,
                      "flicker: the screen white and black on alternate frames (a photodiode); tearing: moving "
                      "vertical bars (the eye)")
      ->check(CLI::IsMember(timing_pattern_names()))
      ->capture_default_str();
  command->add_option("--db", options->db_path, "Results database the session is written to")->capture_default_str();
  command->add_option("--participant", options->participant, "Who or what was tested (the sessions' participant)")
      ->capture_default_str();
  return [=]() {
    options->display = display->display;
    options->request = display->request;
    options->request.title = "glarelab: timing-test";
    options->pattern = parse_timing_pattern(*pattern);
    return report_errors([&]() {
      const TimingTestResult result = run_timing_test(*options, std::cout);
      return result.status == "completed" ? 0 : static_cast<int>(kExitAborted);
    });
  };
}

}  // namespace glarelab::cli
