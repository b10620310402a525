#include <iostream>

#include "core/text_limits.h"
#include "runner/store/session_summary.h"
#include "runner/cli/commands.h"
#include "runner/cli/option_checks.h"
#include "runner/cli/terminal_stream.h"
#include "runner/session/session_runner.h"
#include "runner/session/straylight_session.h"
#include "runner/session/status_line.h"
#include "runner/store/result_store.h"

namespace glarelab::cli {

Action add_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  auto seed = std::make_shared<std::uint64_t>(0);
  auto resume = std::make_shared<std::int64_t>(0);
  auto stop_after = std::make_shared<int>(0);
  auto participant_number = std::make_shared<int>(1);
  CLI::App* run = app.add_subcommand("run", "Run (or resume) an experiment session");
  run->add_option("experiment", options->experiment_path, "Experiment file (TOML)")->required()->check(CLI::ExistingFile);
  run->add_option("--participant", options->participant, "Participant code stored with the session")
      ->capture_default_str();
  run->add_option("--db", options->db_path, "Results database (default: results/<experiment name>.db)");
  auto* display_option = run->add_option("--display", options->display,
                  "Where frames go: window, openxr (a headset through the OpenXR runtime, with a mirror window), "
                  "or offscreen (EGL, else OSMesa; egl or osmesa to insist on one); default: the file's [display] "
                  "output, else window")
      ->check(CLI::IsMember({"window", "openxr", "offscreen", "egl", "osmesa"}))
      ->capture_default_str();
  run->add_option("--observer", options->observer, "Who answers: keyboard, simulated or script:FILE")
      ->capture_default_str();
  run->add_option("--clock", options->clock,
                  "Session clock: real (offscreen frames paced by the wall clock, one refresh period each, and "
                  "stamped on it) or virtual (one period per frame, as fast as the machine renders); default: a "
                  "window's real clock, offscreen virtual unless a live tracker or response device is attached")
      ->check(CLI::IsMember({"real", "virtual"}));
  auto engine = std::make_shared<FrameEngineRequest>(FrameEngineRequest::automatic);
  auto* engine_option = add_choice_option(run, "--engine", *engine,
                                          "Frame engine: cpu, gpu (OpenGL 4.5: GL glare and GL perception stages) or "
                                          "auto (gpu on a hardware GPU with OpenGL 4.5, else cpu); replaces [display] engine");
  auto* participant_number_option =
      run->add_option("--participant-number", *participant_number,
                      "Participant number N >= 1: picks the block order (default: 1 + the sessions of this "
                      "experiment already in the database)")
          ->check(whole_number_check(1, kMaxParticipantNumber));
  auto* seed_option =
      run->add_option("--seed", *seed, "Seed for every random choice (overrides the file's)")->check(seed_check());
  auto* resume_option =
      run->add_option("--resume", *resume, "Finish the remaining trials of this session (same seed and order)")
          ->check(whole_number_check(1, INT64_MAX));
  auto* stop_option = run->add_option("--stop-after", *stop_after,
                                      "Stop after N trials, leaving the session resumable (as if the run had been cut off)")
                          ->check(whole_number_check(1, INT32_MAX));
  run->add_option("--save-frames", options->save_frames_dir,
                  "Write each trial's first stimulus frame (after glare, with the question; linear cd/m2) "
                  "as DIR/trial_NNNN.exr, a record of what was shown");
  // --- tracker (runner/tracker/) ---
  run->add_option("--tracker", options->tracker.spec,
                  "Eye tracker: none, simulated, replay:FILE.csv, replay:FILE.db#SESSION or pupil-labs://HOST:PORT")
      ->capture_default_str();
  run->add_flag("--tracker-optional", options->tracker.optional,
                "Continue without the tracker when it does not answer at start (logged)");
  run->add_option("--pupil-model", options->tracker.pupil_model,
                  "Model pupil: measured diameter, or calibrated (black/white screens, mapped onto 2-8 mm)")
      ->check(CLI::IsMember({"measured", "calibrated"}))
      ->capture_default_str();
  run->add_option("--pupil-calibration-s", options->tracker.calibration_screen_s,
                  "Seconds of each calibration screen (black, then white)")
      ->check(finite_number_in(0.1, 600.0, "s"))
      ->capture_default_str();
  // --- end tracker ---
  // --- response device (docs/DEVICES.md) ---
  run->add_option("--response-device", options->response_device.selector,
                  "USB HID response device (button box, gamepad): VID:PID or VID:PID:USAGE_PAGE in hex "
                  "(glarelab devices lists them)");
  run->add_option("--buttons", options->response_device.buttons,
                  "Its buttons: BYTE:BIT=NAME,... where NAME is a response (or its number) or an adjustment "
                  "action (up, down, coarse_up, coarse_down, fine_up, fine_down, fine_mode, accept)");
  run->add_flag("--response-device-optional", options->response_device.optional,
                "In a window: continue with the keyboard when the response device is absent at start (logged)");
  // --- end response device ---
  return [=]() {
    if (seed_option->count() > 0) options->seed = *seed;
    if (engine_option->count() > 0) options->engine = *engine;
    if (participant_number_option->count() > 0) options->participant_number = *participant_number;
    if (resume_option->count() > 0) options->resume_session_id = *resume;
    if (stop_option->count() > 0) options->stop_after_trials = *stop_after;
    options->display_chosen = display_option->count() > 0;
    return report_errors([&]() {
      RunResult result;
      {
        // The status line until the session ends (cleared then), the session's lines above it.
        std::cout.flush();
        StatusLine status(unescaped_stdout(), StatusLine::stdout_is_terminal());
        options->status = &status;
        result = run_session(*options, status.stream());
        options->status = nullptr;
      }
      const ResultStore store(result.db_path);
      std::cout << summarise_session(store, result.session_id).describe(result.db_path);
      std::cout << describe_straylight_session(store, result.session_id);
      if (!result.tracker_summary.empty()) std::cout << "  " << result.tracker_summary << "\n";
      if (!result.device_summary.empty()) std::cout << "  " << result.device_summary << "\n";
      if (result.status == "running") {
        // Every word shell-quoted (core/text_limits.h): the line is meant to be pasted into a shell.
        std::cout << "  stopped early; finish with: glarelab run " << shell_quoted(options->experiment_path) << " --db "
                  << shell_quoted(result.db_path) << " --resume " << result.session_id << " --display "
                  << shell_quoted(result.display) << " --observer " << shell_quoted(options->observer)
                  << (options->tracker.spec != "none" ? " --tracker " + shell_quoted(options->tracker.spec) : std::string())
                  << (options->response_device.selector.empty()
                          ? std::string()
                          : " --response-device " + shell_quoted(options->response_device.selector) + " --buttons " +
                                shell_quoted(options->response_device.buttons))
                  << "\n";
      }
      return result.status == "aborted" ? static_cast<int>(kExitAborted) : static_cast<int>(kExitOk);
    });
  };
}

}  // namespace glarelab::cli
