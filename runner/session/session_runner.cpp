#include "runner/session/session_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "protocols/experiment.h"
#include "protocols/observer.h"
#include "protocols/procedure.h"
#include "protocols/adjustment_procedure.h"
#include "protocols/stimulus_duration.h"
#include "core/clock.h"
#include "runner/display/compute_context.h"
#include "runner/display/display_backend.h"
#include "runner/session/adjustment_keys.h"
#include "runner/session/device_pause_screen.h"
#include "runner/session/frame_timing.h"
#include "runner/session/interrupt.h"
#include "runner/session/keyboard_responses.h"
#include "runner/session/presentation_overlays.h"
#include "runner/session/refresh_rate_check.h"
#include "runner/session/response_device_input.h"
#include "runner/session/participant_number.h"
#include "runner/session/slow_flip_clock.h"
#include "runner/session/trial_schedule.h"
#include "core/software_version.h"
#include "runner/store/result_store.h"
#include "runner/tracker/real_time_pacer.h"
#include "runner/tracker/tracker_session.h"
#include "core/exr_io.h"
#include "stimuli/frame_renderer.h"
#include "stimuli/glare_stage.h"
#include "stimuli/position_glare.h"
#include "stimuli/scene_library.h"

namespace glarelab {
namespace {

std::string default_db_path(const Experiment& experiment) {
  return (std::filesystem::path("results") / (experiment.name + ".db")).string();
}

// Everything a session needs that comes from the experiment and options, checked before any
// database write.
struct PreparedSession {
  Experiment experiment;
  std::string resolved_config;
  std::unique_ptr<SceneLibrary> scenes;
  std::unique_ptr<Procedure> procedure;
  std::unique_ptr<Observer> observer;  // null for the keyboard
  std::string observer_description;
};

std::unique_ptr<Observer> make_observer(const std::string& spec, const Experiment& experiment, std::string* description) {
  if (spec == "keyboard") {
    *description = "keyboard";
    return nullptr;
  }
  if (spec == "simulated") {
    auto observer = make_simulated_observer(experiment.simulated_observer, experiment.seed);
    *description = observer->description();
    return observer;
  }
  if (spec.starts_with("script:")) {
    auto observer = make_script_observer(spec.substr(7), experiment.presentation.response_window_s > 0.0);
    *description = observer->description();
    return observer;
  }
  throw ConfigError({"--observer", 0, 0}, "observer",
                    "unknown observer '" + spec + "' (choose keyboard, simulated or script:FILE)");
}

PreparedSession prepare(Experiment experiment, const RunOptions& options) {
  PreparedSession prepared;
  prepared.experiment = std::move(experiment);
  prepared.resolved_config = resolved_config_toml(prepared.experiment);
  prepared.scenes = std::make_unique<SceneLibrary>(prepared.experiment.scenes);
  prepared.procedure = make_procedure(prepared.experiment, prepared.scenes->peak_luminances_cd_m2());
  prepared.observer = make_observer(options.observer, prepared.experiment, &prepared.observer_description);
  // --- response device (docs/DEVICES.md): the person answers with it, in a window or offscreen ---
  const bool device = !options.response_device.selector.empty();
  if (device && prepared.observer)
    throw ConfigError({"--response-device", 0, 0}, "response-device",
                      "a response device is answered by a person: use it with --observer keyboard, not " + options.observer);
  if (device && options.display != "window" && options.response_device.optional)
    throw ConfigError({"--response-device-optional", 0, 0}, "response-device-optional",
                      "an offscreen run has no other way to answer than its response device: it cannot be optional");
  if (device && options.display != "window") prepared.observer_description = "response device";
  // --- end response device ---
  if (!prepared.observer && options.display != "window" && !device) {
    throw ConfigError({"--observer", 0, 0}, "observer",
                      "the keyboard observer needs --display window; offscreen runs use --observer simulated or "
                      "script:FILE");
  }
  return prepared;
}

struct TrialRun {
  std::optional<Response> response;  // empty when aborted
  std::vector<FrameRecord> frames;
  std::vector<PhaseFlip> phases;  // parallel to frames
  int other_flips = 0;            // flips that are not stimulus frames (frame_index -1, -2, ...)
  double onset_s = 0.0;
  // When answers start to count: the onset, or in sequential 2-AFC the second interval's onset
  // (keys and device presses before it are logged as ignored).
  double answers_from_s = 0.0;
};

class SessionLoop {
 public:
  SessionLoop(PreparedSession& prepared, DisplayBackend& display, SessionClock& clock, ResultStore& store,
              std::int64_t session_id, TrackerSession& tracker, RealTimePacer* pacer)
      : tracker_(tracker),
        pacer_(pacer),
        prepared_(prepared),
        display_(display),
        clock_(clock),
        store_(store),
        session_id_(session_id),
        renderer_(display.width_px(), display.height_px()),
        period_s_(1.0 / display.refresh_hz()),
        timing_(display.refresh_hz()),
        glare_(prepared.experiment.glare, prepared.experiment.display, prepared.experiment.seed,
               gl::compute_context_factory()),
        overlays_(renderer_, prepared.experiment),
        // Ratings and adjustment never read `layout`: it keeps its default there.
        sequential_(prepared.experiment.forced_choice.layout == "sequential") {
    log_glare_setup();
    for (const auto& [name, scene] : prepared_.scenes->scenes()) textures_.emplace(name, renderer_.upload(scene.image_cd_m2));
  }

  // Returns false when the session was aborted during this trial. The trial runs its schedule
  // (runner/session/trial_schedule.h): inter-trial interval, screens, fixation, interval(s),
  // response, feedback; every flip is stamped and stored with the trial.
  bool run_trial(const TrialPlan& plan, std::ostream& progress) {
    const PresentationSpec& presentation = prepared_.experiment.presentation;
    const TrialSchedule schedule = schedule_trial(presentation, plan, sequential_);
    TrialRun run;
    const bool interactive = prepared_.observer == nullptr;
    // Keys pressed before the trial (late repeats of the previous answer) must not answer it.
    if (interactive) ignore_keys(plan, "pressed before onset");
    if (aborted_) return false;

    // Background after the previous trial, then the screens.
    if (!present_timed_blank(plan, run, FlipPhase::inter_trial, schedule.inter_trial_frames, {})) return false;
    for (const ScreenText& screen : schedule.screens)
      if (!show_screen(plan, screen, run)) return false;

    // Each interval's placements and glare, prepared before the fixation so the timed sequence
    // runs flip after flip; glare frame k of an interval is computed for the time it will flip.
    std::vector<std::vector<Placement>> placements;
    std::vector<std::vector<ImageRGBA>> glare_frames;
    std::vector<PixelRect> stimulus_rects;
    for (int interval = 0; interval < schedule.intervals; ++interval) {
      const TrialPlan shown = interval_plan(plan, interval);
      placements.push_back(layout(shown));
      for (const Placement& placement : placements.back()) stimulus_rects.push_back(placement.rect);
      std::size_t first_flip = 0;
      while (schedule.timed[first_flip].interval != interval) ++first_flip;
      glare_frames.push_back(prepare_glare(shown, placements.back(), static_cast<int>(first_flip)));
    }
    const std::vector<Placement> question = overlays_.question(plan.question, stimulus_rects);

    // The timed sequence: fixation, interval 1 [, inter-stimulus interval, interval 2].
    double sequence_start_s = 0.0;
    for (std::size_t i = 0; i < schedule.timed.size(); ++i) {
      const TimedFlip& flip = schedule.timed[i];
      // Fixation and inter-stimulus flips repeat the frame before them: only its encoding is redrawn.
      const bool repeated = i > 0 && flip.phase != FlipPhase::interval && schedule.timed[i - 1].phase == flip.phase;
      if (repeated) {
        renderer_.encode_to_display(prepared_.experiment.display);
      } else if (flip.phase == FlipPhase::fixation) {
        draw({}, nullptr, overlays_.fixation());
      } else if (flip.phase == FlipPhase::interval) {
        const std::vector<ImageRGBA>& glared = glare_frames[static_cast<std::size_t>(flip.interval)];
        const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(flip.frame_in_interval),
                                                    glared.empty() ? 0 : glared.size() - 1);
        draw(placements[static_cast<std::size_t>(flip.interval)], glared.empty() ? nullptr : &glared[k], question);
      } else {
        draw({}, nullptr, question);
      }
      display_.present();
      const double flip_s = clock_.on_flip();
      after_flip(flip_s);
      if (i == 0) sequence_start_s = flip_s;
      if (i == schedule.onset_flip) run.onset_s = flip_s;
      const double scheduled_s = sequence_start_s + static_cast<double>(i) * period_s_;
      if (flip.stimulus_frame >= 0) {
        // A flip more than 1.5 refresh periods after the previous one means a refresh was missed.
        const bool dropped = timing_.on_flip(flip_s, plan.trial_index, flip.stimulus_frame);
        if (dropped)
          log_late_flip(plan, flip_s, "frame " + std::to_string(flip.stimulus_frame), timing_.dropped().back().interval_s);
        record_flip(run, {flip.phase, flip.interval, flip.stimulus_frame}, scheduled_s, flip_s, dropped);
      } else {
        const std::optional<double> late_s = timing_.on_timed_flip(flip_s);
        if (late_s) log_late_flip(plan, flip_s, std::string(to_string(flip.phase)) + " flip", *late_s);
        record_flip(run, {flip.phase, -1, -1}, scheduled_s, flip_s, late_s.has_value());
      }
      if (i == schedule.first_answer_flip) run.answers_from_s = flip_s;
      if (interactive && i >= schedule.first_answer_flip && !run.response)
        run.response = poll_keyboard(plan, run.onset_s, run.answers_from_s);
      else if (interactive)
        ignore_keys(plan, run.response                       ? "came after the answer"
                          : flip.phase == FlipPhase::fixation ? "pressed before onset"
                                                              : "pressed before the second interval's onset");
      else
        check_interrupt();
      if (aborted_) return false;
    }

    const double window_s = presentation.response_window_s;
    if (!interactive) {
      run.response = prepared_.observer->respond(plan);
      // A script's "abort" ends the session as Escape would; it is not an answer to record.
      if (run.response->value == "abort") {
        aborted_ = true;
        abort_reason_ = "the observer aborted";
        return false;
      }
    } else if (!plan.adjustment_start_cd_m2.empty()) {
      run.response = adjust_interactively(plan, run);
      if (aborted_) return false;
    } else {
      // Response screen: the background (and the question) until an allowed key, Escape, or the
      // end of the response window.
      while (!run.response) {
        if (window_s > 0.0 && clock_.now_s() - run.onset_s >= window_s) {
          run.response = Response{kTimeoutResponse, std::nullopt};
          break;
        }
        draw({}, nullptr, question);
        display_.present();
        const double flip_s = clock_.on_flip();
        timing_.on_flip(flip_s, plan.trial_index, -1);
        after_flip(flip_s);
        record_flip(run, {FlipPhase::response, -1, -1}, flip_s, flip_s, false);
        run.response = poll_keyboard(plan, run.onset_s, run.answers_from_s);
        if (aborted_) return false;
      }
    }
    // An answer after the window closed (a simulated observer's response time) is no answer.
    if (window_s > 0.0 && run.response->response_time_s && *run.response->response_time_s > window_s)
      run.response = Response{kTimeoutResponse, std::nullopt};
    check_interrupt();
    if (aborted_) return false;

    // The answer is in: scored now, shown as feedback, then committed with every flip. An abort
    // during the feedback still commits the answered trial.
    const TrialOutcome outcome = prepared_.procedure->record_response(plan, *run.response);
    const std::string feedback = feedback_text(outcome);
    if (!feedback.empty())
      present_timed_blank(plan, run, FlipPhase::feedback, presentation.feedback_duration.frames,
                          overlays_.centred_text(feedback));
    commit(plan, run, outcome);
    store_.log_event(session_id_, clock_.now_s(), "trial_phases", describe_trial_phases(plan.trial_index, run.phases));
    if (aborted_) return false;
    const int total = prepared_.procedure->planned_trials();
    if (total >= 50 && (plan.trial_index + 1) % (total / 10) == 0)
      progress << "  trial " << plan.trial_index + 1 << "/" << total << "\n" << std::flush;
    return true;
  }

  bool aborted() const { return aborted_; }
  FrameTimingSummary timing_summary() const { return timing_.summary(); }

  // --- response device (runner/session/response_device_input.h) ---
  // `pause_message`: the image shown while the device is unplugged (rendered before the session
  // starts, so a font problem stops the run before anything is written).
  void attach_response_device(ResponseDeviceInput* device, const ImageRGBA& pause_message) {
    device_ = device;
    pause_message_ = renderer_.upload(pause_message);
  }
  // After a device pause the trial in progress ends without being committed (run_trial returns
  // false as for an abort) and is to be run again from its onset; true once per such trial.
  bool take_trial_rerun() {
    if (!rerun_trial_) return false;
    rerun_trial_ = aborted_ = false;
    return true;
  }
  // --- end response device ---
  const std::string& abort_reason() const { return abort_reason_; }

  // --- tracker (runner/tracker/) ---
  // Pupil calibration (Luidolt 2020, 5.2.1 ii): a black, then a white full screen (display peak),
  // each for the configured time; returns false when aborted.
  bool calibrate_pupil() {
    for (const bool black : {true, false}) {
      tracker_.begin_calibration_phase(black);
      const double luminance_cd_m2 = black ? 0.0 : prepared_.experiment.display.peak_luminance_cd_m2;
      const double phase_start_s = clock_.now_s();
      while (clock_.now_s() - phase_start_s < tracker_.calibration_screen_s()) {
        renderer_.compose({}, luminance_cd_m2);
        renderer_.encode_to_display(prepared_.experiment.display);
        display_.present();
        after_flip(clock_.on_flip());
        check_interrupt();
        if (!aborted_ && display_.close_requested()) {
          aborted_ = true;
          abort_reason_ = "window closed";
        }
        if (aborted_) return false;
      }
    }
    tracker_.finish_calibration(clock_.now_s());  // logged as a pupil_calibration event by the tracker logger
    return true;
  }

 private:
  void after_flip(double flip_s) {
    if (pacer_ != nullptr) pacer_->wait_for_next_frame();
    tracker_.on_frame(flip_s);
  }
  TrackerSession& tracker_;
  RealTimePacer* pacer_;
  // --- end tracker ---

  // Double adjustment: the target and both spots stay on screen while the observer adjusts with
  // keys, the wheel or device buttons (runner/session/adjustment_keys.h) until accepted. Each
  // setting is its start times 10^(the log10 steps taken so far).
  // Every flip of the adjustment phase goes into `frames` (a response-phase flip, frame_index < 0).
  std::optional<Response> adjust_interactively(const TrialPlan& plan, TrialRun& run) {
    const double onset_s = run.onset_s;
    TrialPlan shown = plan;
    AdjustmentControl control(prepared_.experiment.adjustment);
    double offset_log10 = 0.0;
    const auto setting = [&](std::size_t spot) { return plan.adjustment_start_cd_m2[spot] * std::pow(10.0, offset_log10); };
    const double comparison_peak_cd_m2 = plan.adjustment_start_cd_m2[0] / plan.scene_scale[0];
    while (true) {
      shown.scene_scale = {setting(0) / comparison_peak_cd_m2, 1.0, setting(1) / comparison_peak_cd_m2};
      draw(layout(shown));
      display_.present();
      const double flip_s = clock_.on_flip();
      timing_.on_flip(flip_s, plan.trial_index, -1);
      after_flip(flip_s);
      record_flip(run, {FlipPhase::response, -1, -1}, flip_s, flip_s, false);
      check_interrupt();
      if (!aborted_ && display_.close_requested()) {
        aborted_ = true;
        abort_reason_ = "window closed";
      }
      if (aborted_) return std::nullopt;
      for (const TimedInput& input : adjustment_inputs(plan, onset_s)) {
        if (input.name == "escape" && input.source == TimedInput::Source::key) {
          aborted_ = true;
          abort_reason_ = "Escape pressed";
          return std::nullopt;
        }
        const AdjustmentStep step = control.apply(input.name, input.shift);
        if (step.effect == AdjustmentEffect::accept)
          return Response{format_adjustment_response(setting(0), setting(1)), input.session_time_s - onset_s};
        if (step.effect == AdjustmentEffect::step) offset_log10 += step.log10_step;
        if (step.effect == AdjustmentEffect::mode_change)
          store_.log_event(session_id_, input.session_time_s, "adjustment_mode",
                           "trial " + std::to_string(plan.trial_index) + ": fine mode " + (control.fine_mode() ? "on" : "off"));
        if (step.effect == AdjustmentEffect::none && device_ != nullptr) device_->log_not_adjusting(plan, input);
        if (step.effect == AdjustmentEffect::none && device_ == nullptr)
          store_.log_event(session_id_, input.session_time_s, "ignored_key",
                           "trial " + std::to_string(plan.trial_index) + ": key '" + input.name + "' does not adjust");
      }
      if (aborted_) return std::nullopt;  // the device pause ended the trial
    }
  }

  // Device presses (stamped when read), then keys and wheel clicks (stamped now), in that order.
  std::vector<TimedInput> adjustment_inputs(const TrialPlan& plan, double onset_s) {
    std::vector<TimedInput> inputs;
    if (device_ != nullptr) {
      bool unplugged = false;
      inputs = device_->adjustment_presses(plan, onset_s, &unplugged);
      if (unplugged && inputs.empty()) {
        pause_for_response_device(plan.trial_index);
        return {};
      }
    }
    for (const InputEvent& event : display_.poll_input())
      inputs.push_back({event.is_key() ? TimedInput::Source::key : TimedInput::Source::wheel, event.name, event.shift,
                        clock_.now_s()});
    return inputs;
  }

  // The device pause: the message on screen until the device is back (the trial is then re-run)
  // or the session is ended; either way the trial in progress ends uncommitted.
  void pause_for_response_device(int trial_index) {
    const auto show_frame = [&] {
      renderer_.compose({centred_placement(*pause_message_, display_.width_px(), display_.height_px())},
                        prepared_.experiment.display.background_cd_m2);
      renderer_.encode_to_display(prepared_.experiment.display);
      display_.present();
      const double flip_s = clock_.on_flip();
      timing_.on_flip(flip_s, trial_index, -1);
      after_flip(flip_s);
    };
    const auto message_pixels = [&] {
      return lit_pixels(renderer_.read_stimulus(), 0.5 * device_pause_text_cd_m2(prepared_.experiment.display));
    };
    const ResponseDeviceInput::PauseResult result = device_->pause(trial_index, display_, clock_, show_frame, message_pixels);
    aborted_ = true;
    if (result.resumed)
      rerun_trial_ = true;
    else
      abort_reason_ = result.abort_reason;
  }

  std::vector<Placement> layout(const TrialPlan& plan) const {
    std::vector<PixelRect> sizes;
    for (const auto& scene_name : plan.scenes) {
      const auto& scene = prepared_.scenes->get(scene_name);
      sizes.push_back({0, 0, scene.image_cd_m2.width_px, scene.image_cd_m2.height_px});
    }
    std::vector<PixelRect> columns;
    const auto rects = side_by_side_layout(display_.width_px(), display_.height_px(), sizes, &columns);
    std::vector<Placement> placements;
    for (std::size_t i = 0; i < plan.scenes.size(); ++i)
      placements.push_back({&textures_.at(plan.scenes[i]), plan.scene_scale.empty() ? 1.0 : plan.scene_scale[i],
                            rects[i], columns[i]});
    return placements;
  }

  // `glared`: the composed frame after glare (prepare_glare), drawn in its place. `overlays` (text,
  // fixation cross) are drawn after glare: they are on the display, not seen through the eye.
  void draw(const std::vector<Placement>& placements, const ImageRGBA* glared = nullptr,
            const std::vector<Placement>& overlays = {}) {
    renderer_.compose(placements, prepared_.experiment.display.background_cd_m2);
    if (glared != nullptr) renderer_.replace_stimulus(*glared);
    if (!overlays.empty()) renderer_.compose_overlay(overlays);
    renderer_.encode_to_display(prepared_.experiment.display);
  }

  // --- presentation (runner/session/trial_schedule.h, presentation_overlays.h) ---
  // What interval `interval` shows: the whole plan side by side, or in a sequential trial the plan
  // narrowed to its position `interval` (its scene alone, centred, with that position's glare).
  TrialPlan interval_plan(const TrialPlan& plan, int interval) const {
    if (!sequential_) return plan;
    const auto i = static_cast<std::size_t>(interval);
    TrialPlan one = plan;
    one.positions = {plan.positions.at(i)};
    one.scenes = {plan.scenes.at(i)};
    one.scene_scale = plan.scene_scale.empty() ? std::vector<double>{} : std::vector<double>{plan.scene_scale.at(i)};
    one.position_glare =
        plan.position_glare.empty() ? std::vector<std::string>{} : std::vector<std::string>{plan.position_glare.at(i)};
    return one;
  }

  // Stimulus flips keep their frame index; every other flip of the trial is numbered -1, -2, ...
  void record_flip(TrialRun& run, const PhaseFlip& phase, double scheduled_s, double flip_s, bool dropped) {
    FrameRecord record;
    record.frame_index = phase.stimulus_frame >= 0 ? phase.stimulus_frame : -(++run.other_flips);
    record.scheduled_s = scheduled_s;
    record.flip_s = flip_s;
    record.dropped = dropped;
    run.frames.push_back(record);
    run.phases.push_back(phase);
  }

  void log_late_flip(const TrialPlan& plan, double flip_s, const std::string& which, double interval_s) {
    store_.log_event(session_id_, flip_s, "dropped_frame",
                     "trial " + std::to_string(plan.trial_index) + " " + which + ": " +
                         std::to_string(1000.0 * interval_s) + " ms since the previous flip");
  }

  // `frames` flips of the background (with `overlays`), timed from the first of them.
  bool present_timed_blank(const TrialPlan& plan, TrialRun& run, FlipPhase phase, int frames,
                           const std::vector<Placement>& overlays) {
    double start_s = 0.0;
    for (int k = 0; k < frames; ++k) {
      // The stimulus framebuffer keeps the frame between these flips: later ones only re-encode it
      // (the display's back buffer is not kept across a swap).
      if (k == 0)
        draw({}, nullptr, overlays);
      else
        renderer_.encode_to_display(prepared_.experiment.display);
      display_.present();
      const double flip_s = clock_.on_flip();
      after_flip(flip_s);
      if (k == 0) start_s = flip_s;
      const std::optional<double> late_s = timing_.on_timed_flip(flip_s);
      if (late_s) log_late_flip(plan, flip_s, std::string(to_string(phase)) + " flip", *late_s);
      record_flip(run, {phase, -1, -1}, start_s + k * period_s_, flip_s, late_s.has_value());
      if (prepared_.observer == nullptr)
        ignore_keys(plan, std::string("pressed during the ") + to_string(phase));
      else
        check_interrupt();
      if (aborted_) return false;
    }
    return true;
  }

  // A text screen until the observer continues: at least screen_min flips; then Space or Enter
  // (keyboard), at once for non-interactive observers. Logged as a 'screen' event.
  bool show_screen(const TrialPlan& plan, const ScreenText& screen, TrialRun& run) {
    const std::vector<Placement> text = overlays_.centred_text(screen.text);
    const int minimum_flips = prepared_.experiment.presentation.screen_min.frames;
    int flips = 0;
    double first_flip_s = 0.0, last_flip_s = 0.0;
    bool proceed = false;
    while (!proceed) {
      if (flips == 0)
        draw({}, nullptr, text);
      else
        renderer_.encode_to_display(prepared_.experiment.display);
      display_.present();
      last_flip_s = clock_.on_flip();
      timing_.on_flip(last_flip_s, plan.trial_index, -1);
      after_flip(last_flip_s);
      if (flips++ == 0) first_flip_s = last_flip_s;
      record_flip(run, {FlipPhase::screen, -1, -1}, last_flip_s, last_flip_s, false);
      const bool long_enough = flips >= minimum_flips;
      if (prepared_.observer != nullptr) {
        check_interrupt();
        proceed = long_enough;
      } else {
        check_interrupt();
        if (!aborted_ && display_.close_requested()) {
          aborted_ = true;
          abort_reason_ = "window closed";
        }
        for (const std::string& key : aborted_ ? std::vector<std::string>{} : display_.poll_keys()) {
          if (key == "escape") {
            aborted_ = true;
            abort_reason_ = "Escape pressed";
            break;
          }
          if ((key == "space" || key == "enter") && long_enough) {
            proceed = true;
            continue;
          }
          store_.log_event(session_id_, clock_.now_s(), "ignored_key",
                           "trial " + std::to_string(plan.trial_index) + " " + screen.kind + " screen: key '" + key +
                               "' " + (key == "space" || key == "enter" ? "before the screen's minimum duration"
                                                                        : "does not continue (Space or Enter)"));
        }
        if (!aborted_ && device_ != nullptr) {
          bool unplugged = false;
          proceed = device_->continues_screen(plan, screen.kind, long_enough, &unplugged) || proceed;
          if (unplugged) pause_for_response_device(plan.trial_index);
        }
      }
      if (aborted_) return false;
    }
    std::ostringstream message;
    message << "trial " << plan.trial_index << ", " << screen.kind << ": '" << first_words(screen.text) << "' shown "
            << flips << " flips (" << last_flip_s - first_flip_s + period_s_ << " s)";
    store_.log_event(session_id_, last_flip_s, "screen", message.str());
    return true;
  }

  // Keys outside the answer period: logged, never an answer; Escape or closing the window ends it.
  void ignore_keys(const TrialPlan& plan, const std::string& why) {
    check_interrupt();
    if (aborted_) return;
    if (display_.close_requested()) {
      aborted_ = true;
      abort_reason_ = "window closed";
      return;
    }
    for (const std::string& key : display_.poll_keys()) {
      if (key == "escape") {
        aborted_ = true;
        abort_reason_ = "Escape pressed";
        return;
      }
      store_.log_event(session_id_, clock_.now_s(), "ignored_key",
                       "trial " + std::to_string(plan.trial_index) + ": key '" + key + "' " + why);
    }
  }

  // "correct" / "wrong" for scored trials, the timeout text for a timeout; empty without feedback
  // or for an answer that has no right or wrong (preference questions, equal sources, ratings).
  std::string feedback_text(const TrialOutcome& outcome) const {
    const PresentationSpec& presentation = prepared_.experiment.presentation;
    if (presentation.feedback == FeedbackKind::none) return "";
    if (outcome.response == kTimeoutResponse) return presentation.feedback_timeout_text;
    if (!outcome.correct) return "";
    return *outcome.correct == 1 ? presentation.feedback_correct_text : presentation.feedback_wrong_text;
  }
  // --- end presentation ---

  // --- glare (stimuli/glare_stage.h) ---
  // The trial's stimulus frames after glare, all prepared before onset: glare on the CPU takes
  // longer than a refresh period (llvmpipe and FFTW), so a window run could not compute it between
  // flips. Frame k is computed for the time it is planned to flip, first_flip + k periods.
  // Control: empty (the composed frame is shown untouched). Static: one frame serves all.
  // Skip decisions are logged once per trial as 'glare_skipped' events.
  // Tracker inputs (when a tracker runs) are those known at preparation, for all the trial's
  // frames: the filtered pupil, the detected blinks (blink_source "tracker") and the latest gaze.
  // `flips_before`: timed flips between now and the first of these frames (fixation, interval 1).
  std::vector<ImageRGBA> prepare_glare(const TrialPlan& plan, const std::vector<Placement>& placements,
                                       int flips_before = 0) {
    const GlareMode mode = glare_mode_for(prepared_.experiment.glare, condition_row(plan));
    // A mode per position (stimuli/position_glare.h): one layer per placement.
    std::vector<GlareMode> position_modes;
    if (plan.position_glare.size() == placements.size())
      for (const std::string& name : plan.position_glare) position_modes.push_back(parse_glare_mode(name));
    const auto is_control = [](GlareMode m) { return m == GlareMode::control; };
    if (position_modes.empty() ? mode == GlareMode::control
                               : std::all_of(position_modes.begin(), position_modes.end(), is_control))
      return {};
    const auto is_dynamic = [](GlareMode m) { return m == GlareMode::dynamic; };
    const bool dynamic = position_modes.empty() ? mode == GlareMode::dynamic
                                                : std::any_of(position_modes.begin(), position_modes.end(), is_dynamic);
    const GlareSpec& spec = prepared_.experiment.glare;
    std::optional<GazePoint> gaze;
    std::optional<TrackerGaze> tracked;
    if (tracker_.active()) {
      const std::optional<double> pupil_mm = tracker_.measured_pupil_mm();
      if (spec.pupil_source == "tracker" && pupil_mm) glare_.record_measured_pupil(clock_.now_s(), *pupil_mm);
      if (spec.blink_source == "tracker") {
        std::vector<DetectedBlink> blinks;
        for (const TrackerBlinkInterval& blink : tracker_.detected_blinks()) blinks.push_back({blink.onset_s, blink.offset_s});
        glare_.set_detected_blinks(blinks);
      }
      // The frames are prepared now and shown from the flip after `flips_before` more: compensation
      // extrapolates to it.
      tracked = spec.gaze_latency_compensation
                    ? tracker_.predicted_gaze(clock_.now_s() + (1 + flips_before) * period_s_)
                    : tracker_.latest_gaze();
      if (tracked) gaze = GazePoint{tracked->x, tracked->y};
    }
    std::vector<GlareLayer> layers;
    std::string modes_label = to_string(mode);
    if (!position_modes.empty()) {
      modes_label.clear();
      for (std::size_t p = 0; p < placements.size(); ++p) {
        renderer_.compose({placements[p]}, 0.0);
        layers.push_back({renderer_.read_stimulus(), position_modes[p]});
        modes_label += (p == 0 ? "" : ", ") + plan.positions.at(p) + " " + to_string(position_modes[p]);
      }
    }
    renderer_.compose(placements, prepared_.experiment.display.background_cd_m2);
    const ImageRGBA composed = renderer_.read_stimulus();
    const double first_flip_s = clock_.now_s() + (1 + flips_before) * period_s_;
    const int count = dynamic ? plan.stimulus_frames : 1;
    std::vector<ImageRGBA> frames;
    int skipped = 0, gratings_hidden = 0, closed = 0;
    std::string skip_reason;
    double smallest_pupil_mm = 1e9;
    std::optional<GazeWindow> window;
    int applications = 0;
    const auto preparation_start = std::chrono::steady_clock::now();
    for (int k = 0; k < count; ++k) {
      const double time_s = first_flip_s + k * period_s_;
      std::vector<GlareFrameReport> reports;
      if (layers.empty()) {
        GlareFrameReport report;
        frames.push_back(glare_.apply(composed, mode, time_s, &report, gaze));
        reports.push_back(report);
      } else {
        frames.push_back(apply_layered_glare(glare_, composed, layers, time_s, gaze, &reports));
      }
      for (const GlareFrameReport& report : reports) {
        ++applications;
        if (report.window && !window) window = report.window;
        if (!report.skip_reason.empty()) {
          ++skipped;
          if (skip_reason.empty()) skip_reason = report.skip_reason;
        }
        if (!report.gratings_in_pupil) ++gratings_hidden;
        if (report.eye_closed && report.convolved) ++closed;  // held PSF; otherwise counted as skipped
        smallest_pupil_mm = std::min(smallest_pupil_mm, report.pupil_diameter_mm);
      }
    }
    if (!presentation_mode_logged_) {
      // Which presentation mode glare trials use, and why (measured on the first one).
      presentation_mode_logged_ = true;
      const double per_frame_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - preparation_start).count() / count;
      store_.log_event(session_id_, clock_.now_s(), "presentation_mode",
                       "glare trials: frames prepared before onset (" + std::to_string(1000.0 * per_frame_s) +
                           " ms per glare frame on this machine against a refresh period of " +
                           std::to_string(1000.0 * period_s_) +
                           " ms; dynamic glare is a function of time and seed, so prepared frames equal live "
                           "ones); control trials: composed live at every refresh");
    }
    const std::string trial = "trial " + std::to_string(plan.trial_index) + " (" + modes_label + "): ";
    const std::string of_frames =
        " of " + std::to_string(applications) + (layers.empty() ? " glare frame(s)" : " glare layer frame(s)");
    if (skipped > 0)
      store_.log_event(session_id_, clock_.now_s(), "glare_skipped",
                       trial + "convolution skipped on " + std::to_string(skipped) + of_frames + ": " + skip_reason);
    if (closed > 0)
      store_.log_event(session_id_, clock_.now_s(), "glare_skipped",
                       trial + "eye closed by a blink on " + std::to_string(closed) + of_frames +
                           ": the PSF of the last open frame is held");
    if (gratings_hidden > 0)
      store_.log_event(session_id_, clock_.now_s(), "glare_skipped",
                       trial + "lens fibre gratings left out on " + std::to_string(gratings_hidden) + of_frames +
                           ": pupil (smallest " + std::to_string(smallest_pupil_mm) +
                           " mm) inside the clear lens centre (cortex annulus from " +
                           std::to_string(2.0 * EyeParameters{}.lens_cortex_inner_radius_mm) + " mm diameter)");
    if (window)
      store_.log_event(session_id_, clock_.now_s(), "glare_window",
                       trial + describe_glare_window(*window, tracked));
    display_.make_current();  // a GL glare backend works in a context of its own
    return frames;
  }

  // Once per session: the glare backend (what and why) and where the eye's inputs come from.
  void log_glare_setup() {
    const GlareSpec& spec = prepared_.experiment.glare;
    bool any_glare = false;
    for (const ConditionRow& row : prepared_.experiment.conditions) {
      const auto sides = position_glare_modes(row);
      any_glare = any_glare || glare_mode_for(spec, row) != GlareMode::control ||
                  (sides && *sides != std::pair{GlareMode::control, GlareMode::control});
    }
    if (!any_glare) {
      store_.log_event(session_id_, clock_.now_s(), "glare_backend", "none: every condition is control");
      return;
    }
    store_.log_event(session_id_, clock_.now_s(), "glare_backend", glare_.backend_reason());
    display_.make_current();  // making a GL backend (or asking GL for auto) changed the current context
    const bool tracked = tracker_.active();
    std::string inputs = std::string("pupil: ") +
                         (tracked && spec.pupil_source == "tracker" ? "the tracker's filtered pupil (model's until its first sample)"
                                                                    : "the eye model's (Eq. 1-2)") +
                         "; blinks: " +
                         (tracked && spec.blink_source == "tracker" ? "detected by the tracker" : "the eye model's schedule");
    if (!tracked && (spec.blink_source == "tracker" || spec.pupil_source == "tracker"))
      inputs += " (no tracker: the model's)";
    if (spec.gaze_window_px > 0)
      inputs += "; gaze window " + std::to_string(spec.gaze_window_px) + " px around " +
                (tracked ? std::string(spec.gaze_latency_compensation
                                           ? "the tracker's gaze extrapolated to each trial's first flip"
                                           : "the tracker's latest gaze (no latency compensation)")
                         : "the display centre: no tracker, no gaze");
    store_.log_event(session_id_, clock_.now_s(), "glare_inputs", inputs);
  }

  static std::string describe_glare_window(const GazeWindow& window, const std::optional<TrackerGaze>& tracked) {
    std::string text = "gaze window " + std::to_string(window.width_px) + "x" + std::to_string(window.height_px) +
                       " px at (" + std::to_string(window.x0_px) + ", " + std::to_string(window.y0_px) + "), centred on ";
    if (tracked)
      return text + "gaze (" + std::to_string(tracked->x) + ", " + std::to_string(tracked->y) + ") from the tracker at " +
             std::to_string(tracked->session_time_s) + " s";
    return text + "the display centre (no gaze)";
  }

  const ConditionRow& condition_row(const TrialPlan& plan) const {
    for (const ConditionRow& row : prepared_.experiment.conditions)
      if (row.name() == plan.condition_name) return row;
    throw std::logic_error("session: trial " + std::to_string(plan.trial_index) + " names condition '" +
                           plan.condition_name + "', which the experiment does not have");
  }
  // --- end glare ---

  void check_interrupt() {
    if (interrupt_requested()) {
      aborted_ = true;
      abort_reason_ = "interrupted (Ctrl-C or SIGTERM)";
    }
  }

  // Response times count from `onset_s`; presses stamped before `answers_from_s` do not answer.
  std::optional<Response> poll_keyboard(const TrialPlan& plan, double onset_s, double answers_from_s) {
    check_interrupt();
    if (aborted_) return std::nullopt;
    if (display_.close_requested()) {
      aborted_ = true;
      abort_reason_ = "window closed";
      return std::nullopt;
    }
    // Every key of the batch is looked at: the first allowed one answers, an Escape anywhere in the
    // batch still ends the session, and the rest are logged, never silently dropped.
    std::optional<Response> answer;
    // Device presses first: they were stamped when read, so before the keys of this poll.
    if (device_ != nullptr) {
      bool unplugged = false;
      answer = device_->answer(plan, onset_s, answers_from_s, &unplugged);
      if (unplugged) pause_for_response_device(plan.trial_index);
      if (aborted_) return std::nullopt;
    }
    for (const std::string& key : display_.poll_keys()) {
      const double key_time_s = clock_.now_s();
      if (key == "escape") {
        aborted_ = true;
        abort_reason_ = "Escape pressed";
        return std::nullopt;
      }
      const auto response = response_for_key(key, plan.allowed_responses);
      if (response && !answer) {
        answer = Response{*response, key_time_s - onset_s};
        continue;
      }
      // Outside the allowed set, or after the answer: logged, never recorded as an answer.
      store_.log_event(session_id_, key_time_s, "ignored_key",
                       "trial " + std::to_string(plan.trial_index) + ": key '" + key + "' " +
                           (response ? "came after the answer" : "is not a response"));
    }
    return answer;
  }

  void commit(const TrialPlan& plan, const TrialRun& run, const TrialOutcome& outcome) {
    TrialRecord record;
    record.session_id = session_id_;
    record.trial_index = plan.trial_index;
    record.block = plan.block;
    record.procedure = plan.procedure;
    record.condition = plan.condition_json;
    record.intensity = outcome.intensity ? outcome.intensity : plan.intensity;
    record.response = outcome.response;
    record.correct = outcome.correct;
    record.staircase = outcome.staircase;
    record.reversal = outcome.reversal;
    record.response_time_s = run.response->response_time_s;
    record.onset_s = run.onset_s;
    record.started_utc = utc_now_iso8601();
    std::vector<AdjustmentSetting> settings;
    for (std::size_t spot = 0; spot < outcome.adjustment_settings_cd_m2.size(); ++spot)
      settings.push_back({static_cast<int>(spot), outcome.adjustment_settings_cd_m2[spot]});
    store_.commit_trial(record, run.frames, settings);
  }

  PreparedSession& prepared_;
  DisplayBackend& display_;
  SessionClock& clock_;
  ResultStore& store_;
  std::int64_t session_id_;
  FrameRenderer renderer_;
  double period_s_;
  std::map<std::string, SceneTexture> textures_;
  FrameTimingMonitor timing_;
  bool presentation_mode_logged_ = false;
  GlareStage glare_;
  PresentationOverlays overlays_;
  bool sequential_;
  bool aborted_ = false;
  std::string abort_reason_;
  ResponseDeviceInput* device_ = nullptr;
  bool rerun_trial_ = false;
  std::optional<SceneTexture> pause_message_;
};

DisplayRequest display_request(const Experiment& experiment) {
  DisplayRequest request;
  request.width_px = experiment.display.width_px;
  request.height_px = experiment.display.height_px;
  request.refresh_hz = experiment.display.refresh_hz;
  request.monitor = experiment.display.monitor;
  request.fullscreen = experiment.display.fullscreen;
  request.title = "glarelab: " + experiment.name;
  return request;
}

}  // namespace

RunResult run_session(const RunOptions& options, std::ostream& progress) {
  install_interrupt_handlers();
  RunResult result;

  // 1. Everything that can be wrong with the input is found before anything is written.
  std::unique_ptr<ResultStore> store;
  std::optional<SessionRecord> resumed;
  std::vector<TrialRecord> done_trials;
  Experiment experiment;
  std::optional<ParticipantNumber> participant;  // of a new session
  if (options.resume_session_id) {
    Experiment from_file = load_experiment(options.experiment_path);
    result.db_path = options.db_path.empty() ? default_db_path(from_file) : options.db_path;
    if (!std::filesystem::exists(result.db_path))
      throw StoreError("SQLite: " + result.db_path + ": no such database to resume from");
    store = std::make_unique<ResultStore>(result.db_path);
    resumed = store->load_session(*options.resume_session_id);
    if (!resumed)
      throw StoreError("SQLite: " + result.db_path + ": no session " + std::to_string(*options.resume_session_id));
    if (resumed->status == "completed")
      throw StoreError("SQLite: " + result.db_path + ": session " + std::to_string(resumed->id) +
                       " is already completed");
    // The stored, fully resolved configuration is the design being finished: same seed, same order.
    experiment = parse_experiment_text(resumed->config, "<session " + std::to_string(resumed->id) + " config>", "/");
    // The block order is the stored one; the file does not carry a session's participant number.
    if (options.participant_number && !experiment.design.blocks.empty() &&
        *options.participant_number != participant_number_of(experiment.design))
      throw ConfigError({"--participant-number", 0, 0}, "participant-number",
                        "session " + std::to_string(resumed->id) + " runs the block order of participant number " +
                            std::to_string(participant_number_of(experiment.design)) + ", not " +
                            std::to_string(*options.participant_number));
    from_file.design.participant_number = experiment.design.participant_number;
    if (resolved_config_toml(from_file) != resumed->config) {
      progress << "note: " << options.experiment_path
               << " differs from the configuration stored with the session; resuming with the stored one\n";
    }
    done_trials = store->load_trials(resumed->id);
    for (std::size_t i = 0; i < done_trials.size(); ++i)
      if (done_trials[i].trial_index != static_cast<int>(i))
        throw StoreError("SQLite: " + result.db_path + ": session " + std::to_string(resumed->id) +
                         " has a gap in its trials at index " + std::to_string(i));
  } else {
    experiment = load_experiment(options.experiment_path);
    if (options.seed) experiment.seed = *options.seed;
    result.db_path = options.db_path.empty() ? default_db_path(experiment) : options.db_path;
    participant = choose_participant_number(options.participant_number, experiment.design.participant_number,
                                            result.db_path, experiment.name);
    experiment.design.participant_number = participant->value;
  }
  PreparedSession prepared = prepare(std::move(experiment), options);
  result.trials_in_design = prepared.procedure->planned_trials();
  const int first_trial = static_cast<int>(done_trials.size());
  // Resume: the committed responses, replayed through the procedure, bring it to the state the
  // interrupted run had (adaptive procedures continue from the same intensity).
  for (const TrialRecord& done : done_trials) {
    const TrialPlan plan = prepared.procedure->next_trial();
    if (plan.condition_json != done.condition)
      throw StoreError("SQLite: " + result.db_path + ": session " + std::to_string(resumed->id) + " trial " +
                       std::to_string(done.trial_index) + " does not match its replay (stored condition " +
                       done.condition + ", replayed " + plan.condition_json + ")");
    prepared.procedure->record_response(plan, Response{done.response, done.response_time_s});
  }

  // --- tracker: source built (bad --tracker value: exit 2) before anything is opened ---
  TrackerSession tracker(options.tracker, prepared.experiment.seed);
  // --- end tracker ---
  ResponseDeviceSession device(options.response_device);  // bad --response-device/--buttons: exit 2

  // 2. The display (a device failure is reported before a session exists).
  auto display = create_display(options.display, display_request(prepared.experiment));
  const std::string renderer = display->gl_info().describe();
  std::unique_ptr<SessionClock> clock;
  // A live tracker or response device needs the real-time clock (and an offscreen run paced in
  // real time).
  if (display->real_time() || tracker.live() || device.configured()) {
    clock = std::make_unique<MonotonicClock>(resumed ? store->last_flip_s(resumed->id) + 1.0 : 0.0);
  } else {
    // Frame k of the session flips at k / refresh_hz, across resumptions too.
    clock = std::make_unique<VirtualClock>(display->refresh_hz(), 0.0, resumed ? store->frame_count(resumed->id) : 0);
  }
  if (options.slow_flip_every)
    clock = std::make_unique<SlowFlipClock>(std::move(clock), display->refresh_hz(), *options.slow_flip_every);

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
  if ((tracker.live() || device.active()) && !display->real_time())
    pacer = std::make_unique<RealTimePacer>(display->refresh_hz());

  // 3. The session row.
  if (!store) store = std::make_unique<ResultStore>(result.db_path);
  if (resumed) {
    result.session_id = resumed->id;
    store->reopen_session(resumed->id);
    store->log_event(result.session_id, clock->now_s(), "resumed",
                     "resumed at trial " + std::to_string(first_trial) + " of " + std::to_string(result.trials_in_design) +
                         " on " + renderer + " (" + options.display + ", " + clock->name() + " clock)");
  } else {
    SessionRecord session;
    session.experiment = prepared.experiment.name;
    session.participant = options.participant;
    session.seed = prepared.experiment.seed;
    session.started_utc = utc_now_iso8601();
    session.status = "running";
    session.config = prepared.resolved_config;
    session.software_version = software_version();
    session.renderer = renderer;
    session.display_backend = display->kind();
    session.clock = clock->name();
    session.observer = prepared.observer_description;
    result.session_id = store->begin_session(session);
    store->log_event(result.session_id, 0.0, "display",
                     display->kind() + " " + std::to_string(display->width_px()) + "x" +
                         std::to_string(display->height_px()) + " at " + std::to_string(display->refresh_hz()) +
                         " Hz, " + renderer + ", " + clock->name() + " clock");
    const std::string rounding =
        describe_duration_rounding(prepared.experiment.forced_choice, prepared.experiment.display.refresh_hz);
    if (!rounding.empty()) store->log_event(result.session_id, 0.0, "duration_rounding", rounding);
    for (const std::string& presentation_rounding :
         describe_presentation_roundings(prepared.experiment.presentation, prepared.experiment.display.refresh_hz))
      store->log_event(result.session_id, 0.0, "duration_rounding", presentation_rounding);
    store->log_event(result.session_id, 0.0, "participant_number",
                     std::to_string(participant->value) + " (" + participant->source + ")");
    for (const auto& [name, scene] : prepared.scenes->scenes()) {
      if (scene.peak_cd_m2 > prepared.experiment.display.peak_luminance_cd_m2) {
        store->log_event(result.session_id, 0.0, "clipping",
                         "scene '" + name + "' peaks at " + std::to_string(scene.peak_cd_m2) +
                             " cd/m2, above the display's " +
                             std::to_string(prepared.experiment.display.peak_luminance_cd_m2) +
                             " cd/m2: brighter pixels are shown at the peak");
      }
    }
  }

  // Durations are frames of [display] refresh_hz: another actual rate scales every one of them.
  const std::string refresh_warning =
      refresh_rate_warning(prepared.experiment.display.refresh_hz, display->refresh_hz());
  if (!refresh_warning.empty()) {
    std::cerr << "warning: " << refresh_warning << "\n";
    store->log_event(result.session_id, clock->now_s(), "refresh_rate", refresh_warning);
  }

  progress << "Session " << result.session_id << " of '" << prepared.experiment.name << "' ("
           << result.trials_in_design << " trials, " << display->kind() << ", " << prepared.observer_description
           << " observer) -> " << result.db_path << "\n";
  if (!prepared.observer && !prepared.procedure->finished()) {
    const TrialPlan first = prepared.procedure->next_trial();
    progress << first.question << " "
             << (first.adjustment_start_cd_m2.empty() ? describe_response_keys(first.allowed_responses)
                                                     : describe_adjustment_keys(prepared.experiment.adjustment))
             << "\n";
  }

  // --- tracker: logged from here on; calibration before the trials ---
  if (tracker_note) store->log_event(result.session_id, clock->now_s(), "tracker_absent", *tracker_note);
  tracker.attach_log(result.db_path, result.session_id);
  // --- end tracker ---
  if (device.active()) store->log_event(result.session_id, clock->now_s(), "response_device", device.description());
  if (device_note) store->log_event(result.session_id, clock->now_s(), "response_device_absent", *device_note);
  ResponseDeviceInput device_input(device, *store, result.session_id);

  // 4. The trials.
  SessionLoop loop(prepared, *display, *clock, *store, result.session_id, tracker, pacer.get());
  if (device.active()) loop.attach_response_device(&device_input, pause_message);
  const bool calibrated = !tracker.wants_calibration() || loop.calibrate_pupil();
  while (calibrated && !prepared.procedure->finished()) {
    if (options.stop_after_trials && result.trials_run_now >= *options.stop_after_trials) {
      result.status = "running";
      result.tracker_summary = tracker.finish(clock->now_s());
      return result;
    }
    if (!loop.run_trial(prepared.procedure->next_trial(), progress)) {
      if (loop.take_trial_rerun()) continue;  // after a device pause: the same trial again
      break;
    }
    ++result.trials_run_now;
  }
  // Frame timing of this run (a resumed session reports the frames shown since resuming).
  const FrameTimingSummary timing = loop.timing_summary();
  store->log_event(result.session_id, clock->now_s(), "frame_timing", timing.describe());
  progress << "Frame timing: " << timing.describe() << "\n";
  result.frames_shown = timing.frames_shown;
  result.frames_dropped = timing.frames_dropped;
  result.tracker_summary = tracker.finish(clock->now_s());
  device.stop();
  result.device_summary = device.summary();
  if (!result.device_summary.empty())
    store->log_event(result.session_id, clock->now_s(), "response_device_summary", result.device_summary);
  if (loop.aborted()) {
    store->log_event(result.session_id, clock->now_s(), "aborted", loop.abort_reason());
    store->finish_session(result.session_id, "aborted");
    result.status = "aborted";
  } else {
    store->finish_session(result.session_id, "completed");
    result.status = "completed";
  }
  return result;
}

}  // namespace glarelab
