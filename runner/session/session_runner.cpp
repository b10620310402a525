// run_session: the order of a session's work, from the checks before any database write to the
// session's final status. Each step lives in a file of its own (runner/session/session_setup.h,
// session_loop.h).
#include "runner/session/session_runner.h"

#include <iostream>
#include <memory>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "protocols/comparison_luminance.h"
#include "protocols/stated_keys.h"
#include "runner/display/headset_gaze.h"
#include "runner/display/openxr_clock.h"
#include "runner/session/adjustment_keys.h"
#include "runner/session/controller_answers.h"
#include "runner/session/device_pause_screen.h"
#include "runner/session/display_thread_priority.h"
#include "runner/session/headset_views.h"
#include "runner/session/interrupt.h"
#include "runner/session/keyboard_responses.h"
#include "runner/session/refresh_rate_check.h"
#include "runner/session/session_loop.h"
#include "runner/session/session_setup.h"
#include "runner/session/status_line.h"
#include "runner/store/lock_wait.h"
#include "runner/tracker/headset_gaze_tracker.h"

namespace glarelab {
namespace {

// Marks a session that failed after its row was written as aborted, with the reason as an
// 'aborted' event. A store that itself failed cannot take the mark: the original error is what
// the caller reports, and the session stays resumable either way.
void end_failed_session(ResultStore& store, std::int64_t session_id, double now_s, const std::string& reason) {
  try {
    store.log_event(session_id, now_s, "aborted", "failed: " + reason);
    store.finish_session(session_id, "aborted");
  } catch (const std::exception&) {
  }
}

// The run's frame timing, logged and printed; flips that do not follow the refresh (no vsync, a
// compositor, another rate) said as a warning, with the likely cause.
void report_frame_timing(ResultStore& store, std::int64_t session_id, double now_s, const FrameTimingSummary& timing,
                         double refresh_hz, std::ostream& progress) {
  store.log_event(session_id, now_s, "frame_timing", timing.describe());
  progress << "Frame timing: " << timing.describe() << "\n";
  const std::string flip_warning = flip_interval_warning(refresh_hz, timing.flip_interval_median_ms / 1000.0);
  if (flip_warning.empty()) return;
  std::cerr << "warning: " << flip_warning << "\n";
  store.log_event(session_id, now_s, "flip_interval", flip_warning);
}

// A lock another process holds on the database makes the session wait, never end (lock_wait.h),
// with a line every 5 s of a wait; Ctrl-C still ends it.
LockWait wait_out_database_locks(ResultStore& store, std::ostream& progress) {
  return LockWait(store.handle(), [&progress, announced_wait_s = 0.0](double waited_s) mutable {
    if (waited_s < announced_wait_s) announced_wait_s = 0.0;  // a new wait
    if (waited_s >= announced_wait_s + 5.0) {
      announced_wait_s = waited_s;
      progress << LockWait::announcement(waited_s);
    }
    return !interrupt_requested();
  });
}

// The session's connection's waits and its trial commits' (runner/session/trial_commit.cpp).
void log_database_locks(ResultStore& store, std::int64_t session_id, double now_s, const LockWait& lock_wait,
                        const LockWait* commit_wait) {
  const int waits = lock_wait.waits() + (commit_wait != nullptr ? commit_wait->waits() : 0);
  if (waits == 0) return;
  const double longest_s = std::max(lock_wait.longest_wait_s(), commit_wait != nullptr ? commit_wait->longest_wait_s() : 0.0);
  store.log_event(session_id, now_s, "database_locked",
                  std::to_string(waits) + " write(s) waited for a lock held by another process, the longest " +
                      std::to_string(longest_s) + " s; nothing was lost");
}

// A virtual clock cannot stamp what happens in real time: a window's flips, a live tracker's
// samples, a response device's presses.
void check_virtual_clock(const RunOptions& options, const TrackerSession& tracker, const ResponseDeviceSession& device) {
  const bool person_display = options.display == "window" || options.display == "openxr";
  if (options.clock == "virtual" && (person_display || tracker.live() || device.configured()))
    throw ConfigError({}, "--clock",
                      std::string("virtual is for offscreen runs without live devices; this run has ") +
                          (options.display == "window" ? "a window" : options.display == "openxr" ? "a headset" : tracker.live() ? "a live tracker" : "a response device") +
                          ", whose times are real");
}

// A headset's head pose at each frame of the trial just run, as the trial's `head_poses` event
// (runner/display/openxr_clock.h); nothing for other displays.
void log_head_poses(ResultStore& store, std::int64_t session_id, int trial_index, DisplayBackend& display,
                    const SessionClock& clock) {
  auto* source = dynamic_cast<HeadPoseSource*>(&display);
  const auto* predicted = dynamic_cast<const PredictedFlipClock*>(&clock);
  if (source == nullptr || predicted == nullptr) return;
  const std::vector<HeadPoseSample> poses = source->take_head_poses();
  if (!poses.empty())
    store.log_event(session_id, clock.now_s(), "head_poses",
                    "trial " + std::to_string(trial_index) + ", " + describe_head_poses(poses, *predicted));
}

// The session's line on the progress stream, and for a person at the keys the first trial's
// question with the keys that answer it.
void announce_session(std::ostream& progress, const RunResult& result, PreparedSession& prepared,
                      const std::string& display_kind) {
  progress << "Session " << result.session_id << " of '" << prepared.experiment.name << "' ("
           << result.trials_in_design << " trials, " << display_kind << ", " << prepared.observer_description
           << " observer) -> " << result.db_path << "\n";
  if (!prepared.observer && !prepared.procedure->finished()) {
    const TrialPlan first = prepared.procedure->next_trial();
    progress << first.question << " "
             << (first.adjustment_start_cd_m2.empty() ? describe_response_keys(first.allowed_responses)
                                                     : describe_adjustment_keys(prepared.experiment.adjustment))
             << "\n";
  }
}

// The overrides change the trial they show, so every trial after it, and a later condition's capture
// would no longer be the frame a seeded session shows: with several conditions they are refused.
void check_preview_overrides(const StimulusPreview& preview) {
  if (preview.conditions.empty()) throw std::invalid_argument("a preview needs a condition");
  if (preview.conditions.size() > 1 && (!preview.comparison_cd_m2.empty() || preview.time_s || preview.glare))
    throw std::invalid_argument("a preview of several conditions shows each as the seeded session does: a comparison "
                                "luminance, a time or a glare mode is for one condition");
}

// A preview (glarelab render) attached to the loop; one condition a procedure would not show is
// shown by it (protocols/comparison_luminance.h).
void attach_preview(SessionLoop& loop, PreparedSession& prepared, const StimulusPreview& preview) {
  check_preview_overrides(preview);
  loop.attach_preview(preview);
  if (preview.conditions.size() == 1)
    show_condition_in_preview(*prepared.procedure, prepared.experiment, preview.conditions.front());
}

std::unique_ptr<DisplayBackend> open_display(const RunOptions& options, const Experiment& experiment) {
  if (options.status) options.status->set_step("opening the display");
  return create_display(options.display, display_request(experiment));
}

// A headset study whose file states no pixel pitch takes the views' (runner/session/headset_views.h;
// their fields of view are known once the runtime's session began), and the scenes' pixels, the
// text's and the glare's follow from the pitch: its display opens before the experiment is prepared
// (after the refusals of an experiment no headset can show), and the views' pitch goes into it.
// Nothing for other displays, or a file that states its pitch (checked against the views later).
// A headset's session always keeps real time: the display's thread is raised before anything opens
// (runner/session/display_thread_priority.h), and the priority is kept here until the display is.
struct HeadsetFirst {
  std::unique_ptr<DisplayBackend> display;
  std::optional<HeadsetDisplayModel> model;
  DisplayThreadPriority display_priority;
};
HeadsetFirst open_headset_first(const RunOptions& options, Experiment& experiment) {
  HeadsetFirst headset;
  if (options.display == "openxr") headset.display_priority = DisplayThreadPriority::raise_before_display();
  if (options.display != "openxr" || stated_key(experiment.source_file, "display", "pixel_pitch_mm").value)
    return headset;
  check_headset_experiment(experiment, options.display, options.display_chosen);
  headset.display = open_display(options, experiment);
  headset.model = headset_display_model(experiment, *headset.display);
  if (headset.model) experiment.display.pixel_pitch_mm = headset.model->pixel_pitch_mm;
  return headset;
}

// The session's display (a headset's open already), its thread raised before it opens where the
// session will keep real time (as make_session_clock decides), a headset's display model, and the
// scenes checked against its views. Threads started after it opened run at normal priority.
std::unique_ptr<DisplayBackend> open_session_display(const RunOptions& options, const PreparedSession& prepared,
                                                     HeadsetFirst& headset, const TrackerSession& tracker,
                                                     const ResponseDeviceSession& device) {
  if (!headset.display_priority.asked() &&
      keeps_real_time(options.display == "window" || options.display == "openxr", tracker, device, options))
    headset.display_priority = DisplayThreadPriority::raise_before_display();
  auto display = headset.display ? std::move(headset.display) : open_display(options, prepared.experiment);
  headset.display_priority.display_opened();
  if (!headset.model) headset.model = headset_display_model(prepared.experiment, *display);  // a pitch refused first
  check_scenes_fit_views(prepared.experiment, *prepared.scenes, *display);
  return display;
}

// What the display brings to the session's log: the priority its thread got (and a note where it
// was refused), a headset's display model (headset_views.h), and a refresh rate other than the
// file's (durations are frames of [display] refresh_hz: another actual rate scales every one of them).
void log_display_setup(ResultStore& store, std::int64_t session_id, double now_s, const PreparedSession& prepared,
                       const DisplayBackend& display, const HeadsetFirst& headset, std::ostream& progress) {
  if (headset.display_priority.asked()) {
    store.log_event(session_id, now_s, "display_priority", headset.display_priority.description());
    if (!headset.display_priority.real_time())
      progress << "note: the display's thread runs at " << headset.display_priority.description() << "\n";
  }
  if (headset.model) store.log_event(session_id, now_s, "display_model", headset.model->description);
  const std::string refresh_warning = refresh_rate_warning(prepared.experiment.display.refresh_hz, display.refresh_hz());
  if (!refresh_warning.empty()) {
    std::cerr << "warning: " << refresh_warning << "\n";
    store.log_event(session_id, now_s, "refresh_rate", refresh_warning);
  }
}

// A headset with an eye tracker gives the gaze when --tracker names no tracker (docs/STEREO.md,
// "Eye gaze"). The stopper returned, declared after the display, stops the tracker before the
// display closes.
TrackerSourceStopper adopt_headset_gaze(TrackerSession& tracker, DisplayBackend& display) {
  if (auto* gaze = dynamic_cast<HeadsetGazeSource*>(&display); gaze != nullptr && gaze->has_eye_gaze())
    tracker.adopt_display_tracker(std::make_unique<HeadsetGazeTracker>(*gaze));
  return TrackerSourceStopper(tracker);
}

}  // namespace

RunResult run_session(const RunOptions& asked, std::ostream& progress) {
  install_interrupt_handlers();
  RunResult result;

  // 1. Everything that can be wrong with the input is found before anything is written.
  if (asked.status) asked.status->set_step("loading the experiment and its scenes");
  SessionStart start = load_session_start(asked, progress);
  const RunOptions options = keep_resumed_clock(display_of_experiment(asked, start.experiment), start);
  result.db_path = start.db_path;
  result.display = options.display;
  HeadsetFirst headset = open_headset_first(options, start.experiment);
  PreparedSession prepared = prepare_session(std::move(start.experiment), options);
  result.scene_notes = scene_load_notes(*prepared.scenes);
  for (const std::string& note : result.scene_notes) progress << "note: " << note << "\n";
  result.trials_in_design = prepared.procedure->planned_trials();
  const int first_trial = static_cast<int>(start.done_trials.size());
  replay_done_trials(*prepared.procedure, start);

  // --- tracker: source built (bad --tracker value: exit 2) before anything is opened ---
  TrackerSession tracker(options.tracker, prepared.experiment.seed);
  ResponseDeviceSession device(options.response_device);  // bad --response-device/--buttons: exit 2

  check_virtual_clock(options, tracker, device);

  // 2. The display (a device failure is reported before a session exists).
  auto display = open_session_display(options, prepared, headset, tracker, device);
  const TrackerSourceStopper tracker_stopper = adopt_headset_gaze(tracker, *display);
  const std::string renderer = display->gl_info().describe();
  std::unique_ptr<SessionClock> clock = make_session_clock(*display, tracker, device, start, options);

  // --- tracker: started on the session clock (absent: TrackerError, exit 3, unless optional) ---
  const std::optional<std::string> tracker_note = tracker.start(*clock);
  std::unique_ptr<RealTimePacer> pacer;
  // --- end tracker ---
  // --- response device: opened on the session clock (absent: DeviceError, exit 3, unless optional) ---
  const std::optional<std::string> device_note = device.start(*clock);
  const ResponseDeviceStopper device_stopper(device);
  const ImageRGBA pause_message =
      device.active() ? device_pause_message_image(prepared.experiment.display, display->width_px()) : ImageRGBA{};
  if (device.active())
    prepared.observer_description =
        (display->real_time() ? "keyboard and response device " : "response device ") + device.description();
  // --- end response device ---
  if ((tracker.live() || device.active() || options.clock == "real") && !display->real_time())
    pacer = std::make_unique<RealTimePacer>(display->refresh_hz());

  // 3. The session row. A participant number counted from the database can be taken by another
  // run between the count and this write (two runs started together): the design is then made
  // again for the next free number, so no two sessions share a block order by accident.
  std::optional<std::int64_t> session_id;
  while (!(session_id = open_session_row(start, prepared, options, *display, *clock, renderer, first_trial,
                                         result.trials_in_design))) {
    start.participant = choose_participant_number(std::nullopt, std::nullopt, start.db_path, prepared.experiment.name);
    prepared.experiment.design.participant_number = start.participant->value;
    const std::string observer_description = prepared.observer_description;  // the device's, when one answers
    prepared = prepare_session(std::move(prepared.experiment), options);
    prepared.observer_description = observer_description;
    result.trials_in_design = prepared.procedure->planned_trials();
  }
  result.session_id = *session_id;
  ResultStore& store = *start.store;
  const LockWait lock_wait = wait_out_database_locks(store, progress);
  // From here on a failure (a GL error mid-run, an observer script that runs out of answers, glare
  // that cannot be computed) ends the session as aborted with its reason, never left running.
  try {

    log_display_setup(store, result.session_id, clock->now_s(), prepared, *display, headset, progress);

    announce_session(progress, result, prepared, display->kind());

    // --- tracker: logged from here on; calibration before the trials ---
    if (tracker_note) store.log_event(result.session_id, clock->now_s(), "tracker_absent", *tracker_note);
    tracker.attach_log(result.db_path, result.session_id);
    // --- end tracker ---
    if (device.active()) store.log_event(result.session_id, clock->now_s(), "response_device", device.description());
    if (device_note) store.log_event(result.session_id, clock->now_s(), "response_device_absent", *device_note);
    ResponseDeviceInput device_input(device, store, result.session_id);
    const auto controllers = ControllerAnswers::of_display(*display, *clock, store, result.session_id);

    // 4. The trials.
    SessionLoop loop(prepared, *display, *clock, store, result.session_id, tracker, pacer.get());
    if (device.active()) loop.attach_response_device(&device_input, pause_message);
    if (controllers) loop.attach_controllers(controllers.get());
    if (options.preview) attach_preview(loop, prepared, *options.preview);
    if (!options.save_frames_dir.empty()) loop.save_first_frames_to(options.save_frames_dir);
    loop.attach_status(options.status);
    if (options.status) options.status->set_step("preparing the first trial");
    const bool calibrated = !tracker.wants_calibration() || loop.calibrate_pupil();
    while (calibrated && !prepared.procedure->finished()) {
      if (options.stop_after_trials && result.trials_run_now >= *options.stop_after_trials) {
        loop.finish_commit(/*write_held_events=*/true);
        result.status = "running";
        result.tracker_summary = tracker.finish(clock->now_s());
        return result;
      }
      TrialPlan plan = prepared.procedure->next_trial();
      if (options.preview && plan.condition_name == options.preview->conditions.front() &&
          !options.preview->comparison_cd_m2.empty())
        plan = with_comparison_luminance(std::move(plan), options.preview->comparison_cd_m2);
      const bool ran = loop.run_trial(plan, progress);
      log_head_poses(store, result.session_id, plan.trial_index, *display, *clock);
      if (!ran) {
        if (loop.take_trial_rerun()) continue;  // after a device pause: the same trial again
        break;
      }
      ++result.trials_run_now;
    }
    loop.finish_commit(/*write_held_events=*/true);  // the last answered trial's commit (trial_commit.cpp)
    store.log_event(result.session_id, clock->now_s(), "trial_commits", loop.commit_summary());

    if (options.preview) {
      result.previews = loop.take_preview_frames();
      result.preview_note = preview_note(*prepared.procedure);
      if (result.previews.empty() && options.preview->conditions.size() == 1)
        throw std::invalid_argument("condition '" + options.preview->conditions.front() + "' is not shown in a session of " +
                                    "participant number " + std::to_string(prepared.experiment.design.participant_number.value_or(1)) +
                                    (loop.aborted() ? " before it ended (" + loop.abort_reason() + ")" : ""));
      store.finish_session(result.session_id, "aborted");
      result.status = "preview";
      return result;
    }

    // 5. The end of the run and the session's status.
    // Frame timing of this run (a resumed session reports the frames shown since resuming).
    const FrameTimingSummary timing = loop.timing_summary();
    report_frame_timing(store, result.session_id, clock->now_s(), timing, display->refresh_hz(), progress);
    result.frames_shown = timing.frames_shown;
    result.frames_dropped = timing.frames_dropped;
    result.tracker_summary = tracker.finish(clock->now_s());
    device.stop();
    result.device_summary = device.summary();
    if (!result.device_summary.empty())
      store.log_event(result.session_id, clock->now_s(), "response_device_summary", result.device_summary);
    log_database_locks(store, result.session_id, clock->now_s(), lock_wait, loop.commit_lock_wait());
    if (loop.aborted()) {
      store.log_event(result.session_id, clock->now_s(), "aborted", loop.abort_reason());
      store.finish_session(result.session_id, "aborted");
      result.status = "aborted";
    } else {
      store.finish_session(result.session_id, "completed");
      result.status = "completed";
    }
    return result;
  } catch (const std::exception& error) {
    end_failed_session(store, result.session_id, clock->now_s(), error.what());
    throw;
  }
}

}  // namespace glarelab
