// Setting a session up before its first trial: what is read and checked before any database
// write, the session clock, and the session row (runner/session/session_setup.h).
#include "runner/session/session_setup.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <utility>

#include "core/atomic_file.h"
#include "core/number_text.h"
#include "glare/wave/psf_scale.h"
#include "protocols/stimulus_duration.h"
#include "runner/display/display_info.h"
#include "runner/display/openxr_clock.h"
#include "runner/session/condition_depth_of_field.h"
#include "runner/session/headset_views.h"
#include "runner/session/condition_refraction.h"
#include "runner/session/scene_fingerprints.h"
#include "runner/session/scene_places.h"
#include "runner/session/slow_flip_clock.h"
#include "runner/session/straylight_session.h"
#include "runner/session/session_eyes.h"
#include "stimuli/glare_stage.h"
#include "core/software_version.h"

namespace glarelab {
namespace {

std::string default_db_path(const Experiment& experiment) {
  return (std::filesystem::path("results") / (experiment.name + ".db")).string();
}

std::unique_ptr<Observer> make_observer(const std::string& spec, const Experiment& experiment, std::string* description) {
  if (spec == "keyboard") {
    *description = "keyboard";
    return nullptr;
  }
  if (spec == "simulated") {
    auto observer = experiment.procedure == "straylight" ? make_simulated_straylight_participant(experiment)
                                                         : make_simulated_observer(experiment.simulated_observer, experiment.seed);
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

// True when a condition with glare uses the wave-optics eye (Ritschel, or the hybrid's or the human eye's near part):
// only that PSF has to fit the display's pixel scale; the analytic models integrate over any pixel.
bool uses_wave_optics_glare(const Experiment& experiment) {
  for (const ConditionRow& row : experiment.conditions) {
    const GlareModel model = glare_model_for(experiment.glare, row);
    if (!uses_wave_optics(model)) continue;
    const auto sides = position_glare_modes(row);
    if (sides ? (sides->first != GlareMode::control || sides->second != GlareMode::control)
              : glare_mode_for(experiment.glare, row) != GlareMode::control)
      return true;
  }
  return false;
}

// Forced choice scores a row by its scenes' peak luminances (protocols/forced_choice.cpp). When
// both peaks are above the display's peak, the display shows both at its white: the difference
// the row asks about is not on the screen, yet one side is scored as correct. Without glare
// (which spreads the excess into halos of different size) nothing else shows it, so such a row
// is refused.
void refuse_rows_the_display_cannot_tell_apart(const Experiment& experiment, const SceneLibrary& scenes) {
  if (experiment.procedure != "forced_choice") return;
  const double peak_cd_m2 = experiment.display.peak_luminance_cd_m2;
  for (const ConditionRow& row : experiment.conditions) {
    const std::string* a = row.find("scene_a");
    const std::string* b = row.find("scene_b");
    if (a == nullptr || b == nullptr) continue;
    const auto sides = position_glare_modes(row);
    const bool glare = sides ? (sides->first != GlareMode::control || sides->second != GlareMode::control)
                             : glare_mode_for(experiment.glare, row) != GlareMode::control;
    const double peak_a = scenes.get(*a).peak_cd_m2, peak_b = scenes.get(*b).peak_cd_m2;
    if (glare || peak_a == peak_b || std::min(peak_a, peak_b) <= peak_cd_m2) continue;
    throw ConfigError(row.where, "",
                      "condition '" + row.name() + "': scenes '" + *a + "' (peak " + number_text(peak_a) +
                          " cd/m2) and '" + *b + "' (peak " + number_text(peak_b) +
                          " cd/m2) are both above the display's peak_luminance_cd_m2 (" + number_text(peak_cd_m2) +
                          "): it shows both at its white, so the difference this row scores is not on the screen. "
                          "Lower their scale_cd_m2, raise the display's peak, or show them with glare, which spreads "
                          "the excess");
  }
}

// A response script answers trial k with its line k, whatever happened before, so the whole
// session can be run on it alone before anything is written: a line that is not an answer to its
// trial, or a script shorter than the design, is found here at its line (ConfigError, exit 2)
// rather than at that trial, after the session row exists. Adaptive procedures follow the
// script's answers to their end as the session would.
void dry_run_script(const Experiment& experiment, const SceneLibrary& scenes, Observer& script) {
  constexpr int kMaxDryRunTrials = 1000000;  // far beyond any design; a safeguard, not a limit
  const std::unique_ptr<Procedure> procedure = make_procedure(experiment, scenes.peak_luminances_cd_m2());
  for (int trial = 0; trial < kMaxDryRunTrials && !procedure->finished(); ++trial) {
    const TrialPlan plan = procedure->next_trial();
    const Response response = script.respond(plan);
    if (response.value == "abort") return;  // the session ends there, as Escape would end it
    procedure->record_response(plan, response);
  }
}

}  // namespace

SessionStart load_session_start(const RunOptions& options, std::ostream& progress) {
  SessionStart start;
  if (options.resume_session_id) {
    Experiment from_file = load_experiment(options.experiment_path);
    start.db_path = options.db_path.empty() ? default_db_path(from_file) : options.db_path;
    if (!std::filesystem::exists(start.db_path))
      throw StoreError("SQLite: " + start.db_path + ": no such database to resume from");
    start.store = std::make_unique<ResultStore>(start.db_path);
    start.resumed = start.store->load_session(*options.resume_session_id);
    if (!start.resumed)
      throw StoreError("SQLite: " + start.db_path + ": no session " + std::to_string(*options.resume_session_id));
    // The session is claimed before anything of it is read: a session another live process runs is
    // refused; one whose process was killed is taken over. Its status and trials are read under
    // the claim, so a run that completes (and lets go) between this process's first look and its
    // claim is seen completed, and is not finished a second time over its own trials.
    start.lease = std::make_unique<SessionLease>(*start.store, start.resumed->id);
    start.resumed = start.store->load_session(*options.resume_session_id);
    if (!start.resumed)
      throw StoreError("SQLite: " + start.db_path + ": session " + std::to_string(*options.resume_session_id) +
                       " was removed while it was claimed");
    // Nothing left to run: what was asked is wrong, the database is fine (exit 2, not 4).
    if (start.resumed->status == "completed")
      throw ConfigError({"--resume", 0, 0}, "resume",
                        "session " + std::to_string(start.resumed->id) + " in " + start.db_path + " is already completed");
    // Another experiment's file names another study: resuming would finish the stored one under
    // the wrong file's name on the command line.
    if (from_file.name != start.resumed->experiment)
      throw ConfigError({options.experiment_path, 0, 0}, "experiment.name",
                        "session " + std::to_string(start.resumed->id) + " in " + start.db_path +
                            " is of experiment '" + start.resumed->experiment + "', not '" + from_file.name +
                            "': resume it with its own experiment file");
    // The stored, fully resolved configuration is the design being finished: same seed, same order.
    start.experiment =
        parse_experiment_text(start.resumed->config, "<session " + std::to_string(start.resumed->id) + " config>", "/");
    // The block order is the stored one; the file does not carry a session's participant number.
    if (options.participant_number && !start.experiment.design.blocks.empty() &&
        *options.participant_number != participant_number_of(start.experiment.design))
      throw ConfigError({"--participant-number", 0, 0}, "participant-number",
                        "session " + std::to_string(start.resumed->id) +
                            " runs the block order of participant number " +
                            std::to_string(participant_number_of(start.experiment.design)) + ", not " +
                            std::to_string(*options.participant_number));
    from_file.design.participant_number = start.experiment.design.participant_number;
    if (resolved_config_toml(from_file) != start.resumed->config) {
      progress << "note: " << options.experiment_path
               << " differs from the configuration stored with the session; resuming with the stored one\n";
    }
    start.done_trials = start.store->load_trials(start.resumed->id);
    for (std::size_t i = 0; i < start.done_trials.size(); ++i)
      if (start.done_trials[i].trial_index != static_cast<int>(i))
        throw StoreError("SQLite: " + start.db_path + ": session " + std::to_string(start.resumed->id) +
                         " has a gap in its trials at index " + std::to_string(i));
    for (const std::string& stored : stored_scene_fingerprints(*start.store, start.resumed->id))
      check_scene_fingerprints(stored, start.experiment.scenes, from_file.scenes, start.resumed->id);
  } else {
    start.experiment = load_experiment(options.experiment_path);
    if (options.seed) start.experiment.seed = *options.seed;
    start.db_path = options.db_path.empty() ? default_db_path(start.experiment) : options.db_path;
    start.straylight_measured = take_measured_straylight(start.experiment, start.db_path, options.participant);
    start.participant = choose_participant_number(options.participant_number,
                                                  start.experiment.design.participant_number, start.db_path,
                                                  start.experiment.name);
    start.experiment.design.participant_number = start.participant->value;
  }
  return start;
}

// --save-frames: the directory made and a file written and removed in it now, so a directory that
// cannot take the frames stops the run before the session row exists.
static void prepare_frame_directory(const std::string& directory) {
  namespace fs = std::filesystem;
  // A file given as the folder (or on its way) is the user's mistake (exit 2), said as such.
  if (const std::optional<std::string> file = file_in_the_way_of_folder(directory))
    throw std::invalid_argument("--save-frames: " + (*file == directory ? directory : directory + ": " + *file) +
                                " is a file, not a directory");
  fs::create_directories(directory);
  if (!fs::is_directory(directory))
    throw fs::filesystem_error("--save-frames: not a directory", fs::path(directory),
                               std::make_error_code(std::errc::not_a_directory));
  const fs::path probe = fs::path(directory) / ".glarelab_write_check";
  {
    std::ofstream out(probe, std::ios::binary);
    out << "check";
    if (!out.flush())
      throw fs::filesystem_error("--save-frames: cannot write frames into the directory", fs::path(directory),
                                 std::make_error_code(std::errc::permission_denied));
  }
  fs::remove(probe);
}

PreparedSession prepare_session(Experiment experiment, const RunOptions& options) {
  PreparedSession prepared;
  prepared.experiment = std::move(experiment);
  if (options.engine) prepared.experiment.engine = *options.engine;  // --engine wins over [display] engine
  prepared.resolved_config = resolved_config_toml(prepared.experiment);
  prepared.scenes = std::make_unique<SceneLibrary>(prepared.experiment.scenes, prepared.experiment.display);
  fit_scenes_to_places(prepared.experiment, *prepared.scenes, /*refuse_misfits=*/false);
  prepared.procedure = make_procedure(prepared.experiment, prepared.scenes->peak_luminances_cd_m2());
  prepared.observer = make_observer(options.observer, prepared.experiment, &prepared.observer_description);
  refuse_rows_the_display_cannot_tell_apart(prepared.experiment, *prepared.scenes);
  if (!options.save_frames_dir.empty()) prepare_frame_directory(options.save_frames_dir);
  if (options.observer.starts_with("script:")) dry_run_script(prepared.experiment, *prepared.scenes, *prepared.observer);
  if (uses_wave_optics_glare(prepared.experiment)) {
    try {
      check_glare_fits_display(prepared.experiment.glare, prepared.experiment.display);
    } catch (const PsfScaleError& error) {
      throw ConfigError({prepared.experiment.source_file, 0, 0}, "glare",
                        std::string("the glare cannot be shown on this [display]: ") + error.what());
    }
  }
  // The observer's refraction in every condition: computable, and sampled by the [glare] grid at
  // the eye's largest pupil (runner/session/condition_refraction.h).
  check_condition_refractions(prepared.experiment);
  // A stereo layout that does not fit each eye's half of the display (runner/session/session_eyes.h).
  check_stereo_layout(prepared.experiment, *prepared.scenes);
  check_depth_of_field(prepared.experiment, *prepared.scenes);
  // --- response device (docs/DEVICES.md): the person answers with it, in a window or offscreen ---
  const bool device = !options.response_device.selector.empty();
  if (device && prepared.observer)
    throw ConfigError({"--response-device", 0, 0}, "response-device",
                      "a response device is answered by a person: use it with --observer keyboard, not " + options.observer);
  check_headset_experiment(prepared.experiment, options.display, options.display_chosen);
  // A window and a headset (its mirror window) have a keyboard at them; offscreen has none.
  const bool person_display = options.display == "window" || options.display == "openxr";
  if (device && !person_display && options.response_device.optional)
    throw ConfigError({"--response-device-optional", 0, 0}, "response-device-optional",
                      "an offscreen run has no other way to answer than its response device: it cannot be optional");
  if (device && !person_display) prepared.observer_description = "response device";
  // --- end response device ---
  if (!prepared.observer && !person_display && !device) {
    throw ConfigError({"--observer", 0, 0}, "observer",
                      "the keyboard observer needs --display window or openxr; offscreen runs use --observer simulated or "
                      "script:FILE");
  }
  return prepared;
}

void replay_done_trials(Procedure& procedure, const SessionStart& start) {
  for (const TrialRecord& done : start.done_trials) {
    const TrialPlan plan = procedure.next_trial();
    if (plan.condition_json != done.condition)
      throw StoreError("SQLite: " + start.db_path + ": session " + std::to_string(start.resumed->id) + " trial " +
                       std::to_string(done.trial_index) + " does not match its replay (stored condition " +
                       done.condition + ", replayed " + plan.condition_json + ")");
    procedure.record_response(plan, Response{done.response, done.response_time_s});
  }
}

DisplayRequest display_request(const Experiment& experiment) {
  DisplayRequest request;
  request.width_px = experiment.display.width_px;
  request.height_px = experiment.display.height_px;
  request.refresh_hz = experiment.display.refresh_hz;
  request.monitor = experiment.display.monitor;
  request.fullscreen = experiment.display.fullscreen;
  request.title = "glarelab: " + experiment.name;
  // The framebuffer depth [display] bits_per_channel asks for (0: the backend's own); the window
  // refuses to open shallower than asked (docs/DISPLAY_CALIBRATION.md).
  request.bits_per_channel = experiment.display.bits_per_channel;
  return request;
}

RunOptions display_of_experiment(RunOptions options, const Experiment& experiment) {
  if (!options.display_chosen && !experiment.display_output.empty()) options.display = experiment.display_output;
  return options;
}

RunOptions keep_resumed_clock(RunOptions options, const SessionStart& start) {
  if (!start.resumed) return options;
  // sessions.clock: "monotonic" or "virtual", "+slow-flips" after it in tests of dropped frames.
  const std::string& stored = start.resumed->clock;
  const bool stored_virtual = stored.rfind("virtual", 0) == 0;
  const std::string session = "session " + std::to_string(start.resumed->id);
  if (stored_virtual && (options.display == "window" || options.display == "openxr"))
    throw ConfigError({"--display", 0, 0}, "display",
                      session + " ran offscreen on the virtual clock; a window runs on the real clock, which would "
                                "break its time line: resume it offscreen");
  const std::string stored_option = stored_virtual ? "virtual" : "real";
  if (!options.clock.empty() && options.clock != stored_option)
    throw ConfigError({"--clock", 0, 0}, "clock",
                      session + " ran on the " + stored + " clock; its onsets and flips are one time line, so it " +
                          "resumes on that clock (--clock " + stored_option + ", or no --clock)");
  options.clock = stored_option;
  return options;
}

bool keeps_real_time(bool display_real_time, const TrackerSession& tracker, const ResponseDeviceSession& device,
                     const RunOptions& options) {
  return display_real_time || tracker.live() || device.configured() || options.clock == "real";
}

std::unique_ptr<SessionClock> make_session_clock(const DisplayBackend& display, const TrackerSession& tracker,
                                                 const ResponseDeviceSession& device, const SessionStart& start,
                                                 const RunOptions& options) {
  std::unique_ptr<SessionClock> clock;
  const double resumed_offset_s = start.resumed ? start.store->last_flip_s(start.resumed->id) + 1.0 : 0.0;
  // A headset's flips are the runtime's predicted display times (runner/display/openxr_clock.h).
  if (const auto* predicted = dynamic_cast<const PredictedFlipSource*>(&display)) {
    clock = std::make_unique<PredictedFlipClock>(*predicted, resumed_offset_s);
  } else if (keeps_real_time(display.real_time(), tracker, device, options)) {
    // A live tracker or response device needs the real-time clock (and an offscreen run paced in
    // real time), as does an offscreen run asked for with --clock real.
    clock = std::make_unique<MonotonicClock>(resumed_offset_s);
  } else {
    // Frame k of the session flips at k / refresh_hz, across resumptions too.
    clock = std::make_unique<VirtualClock>(display.refresh_hz(), 0.0,
                                           start.resumed ? start.store->frame_count(start.resumed->id) : 0);
  }
  if (options.slow_flip_every)
    clock = std::make_unique<SlowFlipClock>(std::move(clock), display.refresh_hz(), *options.slow_flip_every);
  return clock;
}

std::optional<std::int64_t> open_session_row(SessionStart& start, const PreparedSession& prepared, const RunOptions& options,
                              const DisplayBackend& display, const SessionClock& clock, const std::string& renderer,
                              int first_trial, int trials_in_design) {
  if (!start.store) start.store = std::make_unique<ResultStore>(start.db_path);
  ResultStore& store = *start.store;
  if (start.resumed) {
    const std::int64_t session_id = start.resumed->id;
    store.reopen_session(start.resumed->id);
    std::string taken_over;
    if (start.lease->taken_over_from())
      taken_over = "; taken over from " + describe(*start.lease->taken_over_from()) + ", which no longer runs";
    store.log_event(session_id, clock.now_s(), "resumed",
                    "resumed at trial " + std::to_string(first_trial) + " of " + std::to_string(trials_in_design) +
                        " on " + renderer + " (" + options.display + ", " + clock.name() + " clock)" + taken_over);
    return session_id;
  }
  SessionRecord session;
  session.experiment = prepared.experiment.name;
  session.participant = options.participant;
  session.seed = prepared.experiment.seed;
  session.started_utc = utc_now_iso8601();
  session.status = "running";
  session.config = prepared.resolved_config;
  session.software_version = software_version();
  session.renderer = renderer;
  session.display_backend = display.kind();
  session.clock = clock.name();
  session.observer = prepared.observer_description;
  const std::optional<int> earlier = start.participant->earlier_sessions;
  const std::optional<std::int64_t> inserted =
      earlier ? store.begin_session_after(session, *earlier) : std::optional<std::int64_t>(store.begin_session(session));
  if (!inserted) return std::nullopt;
  const std::int64_t session_id = *inserted;
  // Held before anything else is logged; a resume that claimed the new row first (it had to guess
  // its id within milliseconds) runs it, and this run stops here with the holder named.
  start.lease = std::make_unique<SessionLease>(store, session_id);
  store.log_event(session_id, 0.0, "display", describe_display_info(display, clock));
  const std::string rounding =
      describe_duration_rounding(prepared.experiment.forced_choice, prepared.experiment.display.refresh_hz);
  if (!rounding.empty()) store.log_event(session_id, 0.0, "duration_rounding", rounding);
  for (const std::string& presentation_rounding :
       describe_presentation_roundings(prepared.experiment.presentation, prepared.experiment.display.refresh_hz))
    store.log_event(session_id, 0.0, "duration_rounding", presentation_rounding);
  if (!start.straylight_measured.empty())
    store.log_event(session_id, 0.0, "straylight_measured", start.straylight_measured);
  store.log_event(session_id, 0.0, "participant_number",
                  std::to_string(start.participant->value) + " (" + start.participant->source + ")");
  const std::string fingerprints = scene_fingerprints(prepared.experiment.scenes);
  if (!fingerprints.empty()) store.log_event(session_id, 0.0, "scene_fingerprint", fingerprints);
  for (const std::string& note : scene_load_notes(*prepared.scenes)) store.log_event(session_id, 0.0, "scene_load", note);
  for (const auto& [name, scene] : prepared.scenes->scenes()) {
    if (scene.peak_cd_m2 > prepared.experiment.display.peak_luminance_cd_m2) {
      store.log_event(session_id, 0.0, "clipping",
                      "scene '" + name + "' peaks at " + std::to_string(scene.peak_cd_m2) +
                          " cd/m2, above the display's " +
                          std::to_string(prepared.experiment.display.peak_luminance_cd_m2) +
                          " cd/m2: brighter pixels are shown at the peak");
    }
  }
  return session_id;
}

}  // namespace glarelab
