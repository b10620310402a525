#pragma once
// SessionLoop, the trial loop of one session (made by run_session, session_runner.cpp): the state
// every phase of a trial shares; its member functions are defined by phase, in the .cpp file named
// above each group below.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "protocols/procedure.h"
#include "core/clock.h"
#include "runner/display/display_backend.h"
#include "runner/session/condition_refraction.h"
#include "runner/session/controller_answers.h"
#include "runner/session/cpu_composition.h"
#include "runner/session/frame_stream.h"
#include "runner/session/frame_timing.h"
#include "runner/session/interval_glare.h"
#include "runner/session/session_glare.h"
#include "runner/session/presentation_overlays.h"
#include "runner/session/saved_frame_writer.h"
#include "runner/session/response_device_input.h"
#include "runner/session/session_eyes.h"
#include "runner/session/session_setup.h"
#include "runner/session/stimulus_preview.h"
#include "runner/session/trial_schedule.h"
#include "runner/store/lock_wait.h"
#include "runner/store/result_store.h"
#include "runner/tracker/real_time_pacer.h"
#include "runner/tracker/tracker_session.h"
#include "stimuli/frame_renderer.h"
#include "stimuli/glare_stage.h"
#include "stimuli/session_perception.h"

namespace glarelab {

class StatusLine;

// What one run of a trial collected, committed with it (runner/session/trial_commit.cpp).
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
  // runner/session/session_loop.cpp: logs the glare setup and uploads every scene.
  SessionLoop(PreparedSession& prepared, DisplayBackend& display, SessionClock& clock, ResultStore& store,
              std::int64_t session_id, TrackerSession& tracker, RealTimePacer* pacer);
  // runner/session/trial_ahead.cpp: stops and joins the worker preparing a trial ahead.
  ~SessionLoop();
  SessionLoop(const SessionLoop&) = delete;
  SessionLoop& operator=(const SessionLoop&) = delete;

  // runner/session/trial_run.cpp
  // Returns false when the session was aborted during this trial. The trial runs its schedule
  // (runner/session/trial_schedule.h): inter-trial interval, screens, fixation, interval(s),
  // response, feedback; every flip is stamped and stored with the trial.
  bool run_trial(const TrialPlan& plan, std::ostream& progress);

  // A preview (glarelab render, runner/session/stimulus_preview.h): trials of other conditions
  // run with their glare recorded, not computed; the first trial of the condition ends the loop
  // once its first stimulus frame is captured (aborted() is then true).
  void attach_preview(const StimulusPreview& preview) { capture_.preview = &preview; }
  std::vector<PreviewFrame> take_preview_frames() { return std::move(capture_.captured); }
  // Each interval's first stimulus frame (after glare, with overlays; linear cd/m2) written to
  // `directory` as trial_NNNN.exr (a second interval: trial_NNNN_interval_2.exr).
  void save_first_frames_to(const std::string& directory) {
    save_frames_dir_ = directory;
    frame_writer_ = std::make_unique<SavedFrameWriter>();
  }
  // The run's status line (runner/session/status_line.h): each trial's start and its glare
  // preparation are shown on it.
  void attach_status(StatusLine* status) { status_ = status; }

  // runner/session/trial_commit.cpp: waits for the last answered trial's commit (its error
  // rethrown). The session loop calls it before the next answer is taken; the session, before it
  // ends or stops, with `write_held_events`: the events held for a commit that never came (a
  // trial aborted before its answer) are written then.
  void finish_commit(bool write_held_events = false);
  // How this run's trials were committed: the 'trial_commits' event.
  std::string commit_summary() const;
  // The trial commits' lock waits (null before the first commit beside an onset).
  const LockWait* commit_lock_wait() const { return commit_lock_wait_.get(); }

  bool aborted() const { return aborted_; }
  const std::string& abort_reason() const { return abort_reason_; }
  FrameTimingSummary timing_summary() const { return timing_.summary(); }

  // --- response device (runner/session/response_device_input.h) ---
  // runner/session/response_device_pause.cpp
  // `pause_message`: the image shown while the device is unplugged (rendered before the session
  // starts, so a font problem stops the run before anything is written).
  void attach_response_device(ResponseDeviceInput* device, const ImageRGBA& pause_message);
  // After a device pause the trial in progress ends without being committed (run_trial returns
  // false as for an abort) and is to be run again from its onset; true once per such trial.
  bool take_trial_rerun();
  // --- end response device ---
  // A headset's controllers (runner/session/controller_answers.h): they answer and continue screens.
  void attach_controllers(ControllerAnswers* controllers) { controllers_ = controllers; }

  // --- tracker (runner/tracker/) ---
  // runner/session/session_loop.cpp
  // Pupil calibration (Luidolt 2020, 5.2.1 ii): a black, then a white full screen (display peak),
  // each for the configured time; returns false when aborted.
  bool calibrate_pupil();
  // --- end tracker ---

 private:
  // runner/session/trial_presentation.cpp: drawing and presenting the flips of a trial.
  std::vector<Placement> layout(const TrialPlan& plan) const;
  // `glared`: where the frame after glare differs from the composed one (interval_glare.h), drawn over it. `overlays` (text,
  // fixation cross) are drawn after glare: they are on the display, not seen through the eye.
  void draw(const std::vector<Placement>& placements, const GlaredRegion* glared = nullptr,
            const std::vector<Placement>& overlays = {});
  // What interval `interval` shows: the whole plan side by side, or in a sequential trial the plan
  // narrowed to its position `interval` (its scene alone, centred, with that position's glare).
  TrialPlan interval_plan(const TrialPlan& plan, int interval) const;
  // Flipping, and the flip's time on the session clock: a preview's fast-forward (the trials
  // before the one it captures) advances the clock flip by flip without drawing or presenting
  // anything. An offscreen run on the real clock then waits for the next refresh boundary, as a
  // window's swap waits for the vertical blank, and the flip is stamped at that boundary
  // (runner/tracker/real_time_pacer.h).
  double present() {
    if (pacer_ == nullptr) {
      if (!fast_forward_) display_.present();
      return clock_.on_flip();
    }
    // An offscreen display's present waits for the frame's GL work to finish (glFinish), which
    // with a software renderer is CPU work: the flip's drawing, not a wait for the refresh.
    const auto present_start = std::chrono::steady_clock::now();
    if (!fast_forward_) display_.present();
    timing_.add_work(FlipWork::drawing,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - present_start).count());
    return clock_.on_flip_at(pacer_->wait_for_next_frame());
  }
  // Encodes the stimulus framebuffer into the display's, unless an offscreen display still holds
  // its encoding (runner/session/trial_presentation.cpp).
  void encode();
  // Stimulus flips keep their frame index; every other flip of the trial is numbered -1, -2, ...
  void record_flip(TrialRun& run, const PhaseFlip& phase, double scheduled_s, double flip_s, bool dropped,
                   std::optional<double> gaze_age_s = std::nullopt);
  void log_late_flip(const TrialPlan& plan, double flip_s, const std::string& which, double interval_s);
  // A 'late_onset' event: the onset's interval since the flip before it and its likely cause.
  void log_late_onset(const TrialPlan& plan, double flip_s, const LateOnset& late);
  // `frames` flips of the background (with `overlays`), timed from the first of them.
  // continues_blank: these flips go on a blank already shown (the inter-trial interval after its
  // glare was prepared): the first one's distance from the last flip is no late flip, nothing
  // having changed on the screen.
  bool present_timed_blank(const TrialPlan& plan, TrialRun& run, FlipPhase phase, int frames,
                           const std::vector<Placement>& overlays, bool continues_blank = false);
  // A text screen until the observer continues: at least screen_min flips; then Space or Enter
  // (keyboard), at once for non-interactive observers. Logged as a 'screen' event.
  bool show_screen(const TrialPlan& plan, const ScreenText& screen, TrialRun& run);
  // After every flip: the tracker's per-frame poll.
  void after_flip(double flip_s) { tracker_.on_frame(flip_s); }

  // runner/session/trial_run.cpp
  // A trial's intervals set up before the fixation: each one's plan as shown, placements and glare
  // (frames prepared before onset where so presented), and where its stimuli lie (the question
  // goes above them). False when the session was interrupted meanwhile.
  struct TrialIntervals {
    std::vector<TrialPlan> shown_plans;
    std::vector<std::vector<Placement>> placements;
    std::vector<IntervalGlare> glare;
    std::vector<PixelRect> stimulus_rects;
  };
  bool begin_intervals(const TrialPlan& plan, const TrialSchedule& schedule, int flips_after, bool prepare_in_interval,
                       TrialIntervals& intervals);
  // The timed sequence (fixation, interval 1 [, inter-stimulus interval, interval 2]), flip by
  // flip; false when the session was aborted (or a preview captured its frame).
  bool run_timed_sequence(const TrialPlan& plan, const TrialSchedule& schedule, TrialIntervals& intervals,
                          const std::vector<Placement>& question, TrialRun& run);
  // The answer: the observer's, an adjustment, or keys on the response screen until the window
  // closes; false when the session was aborted.
  bool collect_response(const TrialPlan& plan, const std::vector<Placement>& question, TrialRun& run);
  // "correct" / "wrong" for scored trials, the timeout text for a timeout; empty without feedback
  // or for an answer that has no right or wrong (preference questions, equal sources, ratings).
  std::string feedback_text(const TrialOutcome& outcome) const;

  // runner/session/trial_answers.cpp: keys, device presses and interrupts while a trial runs.
  void check_interrupt();
  // Keys outside the answer period: logged, never an answer; Escape or closing the window ends it.
  void ignore_keys(const TrialPlan& plan, const std::string& why);
  // Response times count from `onset_s`; presses stamped before `answers_from_s` do not answer.
  std::optional<Response> poll_keyboard(const TrialPlan& plan, double onset_s, double answers_from_s);

  // runner/session/adjustment_phase.cpp
  // Double adjustment: the target and both spots stay on screen while the observer adjusts with
  // keys, the wheel or device buttons (runner/session/adjustment_keys.h) until accepted. Each
  // setting is its start times 10^(the log10 steps taken so far).
  // Every flip of the adjustment phase goes into `frames` (a response-phase flip, frame_index < 0).
  std::optional<Response> adjust_interactively(const TrialPlan& plan, TrialRun& run);
  // Device presses (stamped when read), then keys and wheel clicks (stamped now), in that order.
  std::vector<TimedInput> adjustment_inputs(const TrialPlan& plan, double onset_s);

  // runner/session/response_device_pause.cpp
  // The device pause: the message on screen until the device is back (the trial is then re-run)
  // or the session is ended; either way the trial in progress ends uncommitted.
  void pause_for_response_device(int trial_index);


  // runner/session/real_stimulus_trial.cpp: a trial showing a physical object (TrialPlan::
  // real_stimulus): its interval without glare or perception stages (captured by a preview like any
  // other), and the instruction to look at the object, centred (empty for an image).
  IntervalGlare begin_real_stimulus(const TrialPlan& plan, int flips_before);
  std::vector<Placement> real_stimulus_instruction_overlay(const TrialPlan& plan);

  // runner/session/straylight_trial.cpp: a straylight trial (TrialPlan::straylight): its images
  // uploaded once per session (nothing for other procedures), frame k of its interval (the ring in
  // the first half of each flicker cycle, the compensation light in the second), and its
  // interval, without glare or perception stages.
  void upload_straylight_stimulus();
  std::vector<Placement> straylight_frame(const TrialPlan& plan, int frame_in_interval) const;
  IntervalGlare begin_straylight(const TrialPlan& plan, int flips_before);
  // With --save-frames: the display's drive values of each frame of a straylight trial's first
  // flicker cycle, as the window is sent them, trial_NNNN_drive_KK.exr (the flicker read back).
  void save_straylight_cycle_frame(const TrialPlan& plan, int frame_in_interval);

  // runner/session/trial_run.cpp: at an interval's first flip, before it is presented, for the
  // previewed trial: the frame captured. True when the preview is done.
  bool capture_first_frame(const TrialPlan& plan, int interval);
  // Right after an interval's first flip (--save-frames): the stimulus framebuffer, which still
  // holds the frame shown, read back and handed to the writer. After the flip, not before it: the
  // read-back (which also waits for the frame's GL work) does not delay the onset.
  void save_first_frame(const TrialPlan& plan, int interval);

  // runner/session/trial_ahead.cpp: the next trials prepared while this one runs (docs/TIMING.md,
  // "Trials prepared ahead").
  // After a stimulus flip of the current trial, once none of its frames is left to compute live on
  // this thread: the trials the procedure knows come next (Procedure::peek_following_trial), up to
  // kTrialsAhead of them, are laid out here, on the display's thread, and a worker thread for each
  // composes its scenes on the CPU (CpuComposition; in GL here first, for the next trial only,
  // where that is not GL's frame bit for bit), begins its glare and computes its frames beside the
  // current trial's remaining flips, its answer and the next inter-trial intervals. The workers run
  // one after another, in the order the trials are shown (the eyes' engines are one worker's at a
  // time). `flip`: the index in `schedule.timed` of the flip just made, at `flip_s`.
  void begin_trial_ahead(const TrialPlan& current, const TrialSchedule& schedule, std::size_t flip, double flip_s,
                         const TrialIntervals& shown);
  // One trial prepared ahead, `plan` with `plan_schedule`, taken at `start_s` as planned (its first
  // flip one period later), beside trial `beside`; its worker starts once the worker before it has
  // finished. False, with nothing begun, where its scenes would be composed in GL on this thread
  // and `may_compose_in_gl` is not set.
  bool begin_one_trial_ahead(const TrialPlan& plan, const TrialSchedule& plan_schedule, double start_s, int beside,
                             bool may_compose_in_gl);
  // Why `plan` (nullptr: none known) is not prepared ahead; empty when it is.
  std::string why_not_ahead(const TrialPlan* plan, const TrialSchedule* plan_schedule);
  // Whether the next trial prepared ahead is `plan` (nothing is prepared ahead: false).
  bool trial_ahead_matches(const TrialPlan& plan) const;
  // At the next trial, after its inter-trial interval and screens: true when `plan` is the trial
  // prepared ahead (the same plan, and on the virtual clock frames timed for the same flips as
  // preparing them now would), its intervals moved into `intervals` once the worker has finished
  // (the wait counted as glare preparation). False: prepared now, as without a worker.
  bool take_trial_ahead(const TrialPlan& plan, const TrialSchedule& schedule, TrialIntervals& intervals);
  // Stops the workers at their next frame and joins them; what they prepared is dropped.
  void drop_trial_ahead();
  // The trial taken at its onset while its worker still makes its frames (FrameStream): the frame
  // a stimulus flip of `interval` shows, waited for (nullptr where the interval computes none);
  // false when no stream covers it (the frame is then the interval's own, computed as without a
  // worker). The wait is glare preparation in the flip's work.
  bool streamed_frame(int interval, int k, const GlaredRegion*& frame);
  // Once the stream is complete (or at once, `stop`: the trial ended early): joins its worker,
  // rethrows its error, and counts its frames into the trial's preparation.
  void finish_stream(bool stop = false);
  // Once per trial with computed frames: a 'trial_preparation' event saying where its frames were
  // computed and how many were left to compute at its onset.
  void log_trial_preparation(const TrialPlan& plan, const TrialIntervals& intervals);

  // runner/session/trial_commit.cpp
  // The answered trial's row, adjustments and flips in one transaction, then its trial_phases
  // event, on a thread of its own with a second connection to the database, beside the next
  // trial's start; `progress_line` (may be empty) is written to `progress` once it is committed.
  void commit(const TrialPlan& plan, const TrialRun& run, const TrialOutcome& outcome, std::string progress_line,
              std::ostream& progress);

  // Initialised in this order (the overlays draw with the renderer).
  TrackerSession& tracker_;
  RealTimePacer* pacer_;
  PreparedSession& prepared_;
  DisplayBackend& display_;
  SessionClock& clock_;
  ResultStore& store_;
  std::int64_t session_id_;
  FrameRenderer renderer_;
  double period_s_;
  std::map<std::string, SceneTexture> textures_;
  // The same scenes composed on the CPU, for the worker preparing a trial ahead.
  CpuComposition composition_;
  std::vector<SceneTexture> straylight_textures_;  // ring, left half, right half
  PixelRect straylight_rect_;
  FrameTimingMonitor timing_;
  PreviewCapture capture_;
  // The session's glare and perception (runner/session/session_glare.h).
  SessionGlare glare_;
  PresentationOverlays overlays_;
  bool sequential_;
  bool aborted_ = false;
  std::string abort_reason_;
  ResponseDeviceInput* device_ = nullptr;
  ControllerAnswers* controllers_ = nullptr;
  bool rerun_trial_ = false;
  std::optional<SceneTexture> pause_message_;
  bool fast_forward_ = false;
  std::string save_frames_dir_;
  // The saved frames' files written beside the session (saved_frame_writer.h); its thread starts
  // after the display opened, at normal priority.
  std::unique_ptr<SavedFrameWriter> frame_writer_;
  StatusLine* status_ = nullptr;
  // What draw() last composed into the stimulus framebuffer (scenes, the glared region's serial or
  // 0 for none, overlays), and the renderer's write count after it: a flip of the same frame only
  // re-encodes.
  struct DrawnFrame {
    std::uint64_t generation = 0;
    std::vector<Placement> placements, overlays;
    std::uint64_t glared_serial = 0;
    PixelRect glared_box;  // where that region lies (0 x 0 without one)
  };
  std::optional<DrawnFrame> drawn_;
  // The trial being prepared ahead (runner/session/trial_ahead.cpp), and this trial's own record of
  // how its frames came: prepared ahead beside the trial before (and how long the onset waited for
  // them), or before its onset.
  struct TrialAhead {
    TrialPlan plan;
    TrialIntervals intervals;
    int beside_trial = -1;
    double layout_s = 0.0;               // laid out (and its glare begun where GL composes it), on the display's thread
    std::vector<double> first_flip_s;    // per interval: when its first stimulus frame is planned to flip
    // Its scenes composed on the CPU by the worker (CpuComposition::exact), or in GL on the display's
    // thread before the worker starts; and the stimulus framebuffer's writes that made on that thread.
    bool composed_on_worker = false;
    std::uint64_t display_writes = 0;
    std::vector<int> frames_to_compute;  // per interval: all (-1) or none (0); the worker's
    // When it is planned to be taken (its schedule's first flip one period later), its schedule's
    // timed flips and the feedback flips predicted after its answer: where the trial after it goes.
    double start_s = 0.0;
    std::size_t timed_flips = 0;
    int feedback_flips = 0;
    FrameStream stream;                  // the frames, as the worker makes them
    std::thread worker;
    std::atomic<bool> stop{false};
    std::exception_ptr error;
    int frames = 0;  // computed by the worker
    double worker_s = 0.0;  // from its start, after the worker before it finished
    std::promise<void> worker_done;  // set when its worker ends, however it ends
  };
  // How many trials are prepared ahead of the one shown: two, so that a trial whose frames take
  // longer than the trial before it leaves (two dynamic trials in a row on two cores) borrows the
  // time a quicker trial before them left over. Each holds its frames until it is shown (the
  // demo's dynamic trial: 30 frames of 3 MB, half floats of the glared region).
  static constexpr std::size_t kTrialsAhead = 2;
  // The trials prepared ahead, the next one first.
  std::deque<std::unique_ptr<TrialAhead>> ahead_;
  // On its worker: the trial's scenes composed and glare begun (where GL did not do that on the
  // display's thread), then its frames made and published in the order they are shown.
  void make_frames_ahead(TrialAhead& ahead);
  // The end of the last worker started (invalid: none yet): the next one waits for it.
  std::shared_future<void> last_worker_done_;
  // The trial shown now, taken before its worker was done: its intervals are the trial's own
  // (moved out), the worker making their remaining frames in place.
  std::unique_ptr<TrialAhead> streaming_;
  bool ahead_begun_ = false;  // for the trial running now
  bool trial_begun_in_run_ = false;  // a trial of this run has begun (the first prepares the next before its onset)
  std::string next_not_ahead_;  // why the next trial is not being prepared ahead
  struct TrialPreparation {
    bool ahead = false;
    int beside_trial = -1;
    int worker_frames = 0;     // glare frames the worker computed
    double worker_s = 0.0;     // its wall time
    double layout_ms = 0.0;    // laying the trial out (and beginning its glare in GL), on the display's thread
    bool composed_on_worker = false;
    std::uint64_t display_writes = 0;  // to the stimulus framebuffer, for it, on the display's thread
    double onset_wait_s = 0.0; // how long the trial waited for the worker after its inter-trial interval
    int ready_at_onset = -1;   // frames the worker had made at the onset (-1: all, it was done)
    double flip_wait_s = 0.0;  // how long the trial's flips waited for the rest
    std::string not_ahead;     // why the trial was not prepared ahead (empty when it was)
    int onset_frames_computed = 0;  // glare frames computed on the display's thread before the onset flip
  };
  TrialPreparation preparation_;
  // The commit in flight (runner/session/trial_commit.cpp): its thread and connection, its error,
  // and the progress line said once it is in.
  std::unique_ptr<ResultStore> commit_store_;
  // Its lock wait for the session's life (a lock another process holds is waited out and counted,
  // as on the session's own connection), the wait in progress, and the commit's end.
  std::unique_ptr<LockWait> commit_lock_wait_;
  std::atomic<double> commit_waited_s_{0.0};
  std::future<void> commit_finished_;
  std::thread committer_;
  std::exception_ptr commit_error_;
  std::string pending_progress_;
  std::ostream* pending_progress_stream_ = nullptr;
  // Events of the trial written with its commit rather than between its flips or before the next
  // onset: its trial_preparation, its dropped frames, its glare's (SessionGlare::hold_trial_events_in).
  std::vector<HeldEvent> events_with_commit_;
  int commits_beside_ = 0;   // on the committer's thread
  int commits_at_once_ = 0;  // on the display's thread (an in-memory database)
};

}  // namespace glarelab
