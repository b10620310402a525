// One trial's schedule run flip by flip, from the inter-trial interval to the commit: the timed
// sequence stamped on the session clock, the answer (keys, response device, adjustment or a
// non-interactive observer), scoring and feedback.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/exr_io.h"
#include "protocols/observer.h"
#include "protocols/procedure.h"
#include "runner/session/session_loop.h"
#include "runner/session/status_line.h"
#include "runner/session/trial_schedule.h"

namespace glarelab {
namespace {

// The kind of work an interval's frames are, for the causes of late onsets (frame_timing.h).
FlipWork work_kind(const IntervalGlare& glare) {
  return glare.perceived() ? FlipWork::perception : FlipWork::glare_preparation;
}

}  // namespace

bool SessionLoop::run_trial(const TrialPlan& plan, std::ostream& progress) {
  const PresentationSpec& presentation = prepared_.experiment.presentation;
  if (status_)
    status_->set_trial(plan.trial_index + 1, prepared_.procedure->planned_trials(),
                       plan.block_name.empty() ? std::string() : "block '" + plan.block_name + "'");
  const TrialSchedule schedule = schedule_trial(presentation, plan, sequential_);
  const bool first_of_run = !trial_begun_in_run_;
  trial_begun_in_run_ = true;
  TrialRun run;
  // A trial prepared ahead beside the one before (runner/session/trial_ahead.cpp) takes its frames
  // after its inter-trial interval; any other prepared trial is dropped.
  preparation_ = TrialPreparation{};
  preparation_.not_ahead = next_not_ahead_;
  next_not_ahead_.clear();
  ahead_begun_ = false;
  const bool ahead = trial_ahead_matches(plan);
  if (!ahead) {
    if (!ahead_.empty()) preparation_.not_ahead = "the trial shown is not the one prepared";
    drop_trial_ahead();
  }
  fast_forward_ = capture_.preview != nullptr && !capture_.captures(plan);
  const bool interactive = prepared_.observer == nullptr;
  // Keys pressed before the trial (late repeats of the previous answer) must not answer it.
  if (interactive) ignore_keys(plan, "pressed before onset");
  if (aborted_) return false;

  // Background after the previous trial, then the screens. Glare frames prepared before onset are
  // computed during the inter-trial interval when no screen comes between (and no tracker gives
  // the gaze, which is then taken as late as it can be): after the interval's first flip, its
  // remaining flips shortened by the refresh boundaries that passed meanwhile. So on a real clock
  // the blank lasts the interval whether a trial's glare is prepared, live or absent, rather than
  // the interval plus the preparation; on the virtual clock the flips are the same either way.
  const bool prepare_in_interval =
      !ahead && schedule.screens.empty() && schedule.inter_trial_frames > 1 && !tracker_.active();
  const int interval_flips_first = prepare_in_interval ? 1 : schedule.inter_trial_frames;
  const int interval_flips_after = schedule.inter_trial_frames - interval_flips_first;  // as planned
  if (!present_timed_blank(plan, run, FlipPhase::inter_trial, interval_flips_first, {})) return false;
  const double interval_start_s = run.frames.empty() ? clock_.now_s() : run.frames.back().flip_s;
  for (const ScreenText& screen : schedule.screens)
    if (!show_screen(plan, screen, run)) return false;

  // Each interval's placements and glare, prepared before the fixation so the timed sequence
  // runs flip after flip.
  TrialIntervals intervals;
  // A worker still making the trial's frames in `intervals` is stopped and joined before they go,
  // however the trial ends; once the frames are all shown it is done (finish_stream).
  struct StreamStop {
    SessionLoop& loop;
    ~StreamStop() { loop.finish_stream(/*stop=*/true); }
  } stream_stop{*this};
  if (!(ahead && take_trial_ahead(plan, schedule, intervals)) &&
      !begin_intervals(plan, schedule, interval_flips_after, prepare_in_interval, intervals))
    return false;
  if (prepare_in_interval) {
    // The interval's flips were planned one a period after its first; those whose boundary passed
    // while the frames were prepared are left out (none on the virtual clock, where now is the
    // next flip's time).
    const double elapsed_periods = (clock_.now_s() - interval_start_s) / period_s_;
    const int passed = std::max(0, static_cast<int>(std::ceil(elapsed_periods - 1e-6)) - 1);
    if (!present_timed_blank(plan, run, FlipPhase::inter_trial, std::max(0, interval_flips_after - passed), {},
                             /*continues_blank=*/true))
      return false;
  }
  // The question above the stimuli; a real stimulus's instruction stands where its image would,
  // and stays up with the question until the answer.
  const std::vector<Placement> instruction = real_stimulus_instruction_overlay(plan);
  for (const Placement& placement : instruction) intervals.stimulus_rects.push_back(placement.rect);
  std::vector<Placement> question = instruction;
  for (const Placement& placement : overlays_.question(plan.question, intervals.stimulus_rects)) question.push_back(placement);

  // The run's first trial on a real clock: the trial after it is prepared before its first flip,
  // and waited for. Beside the first trial the worker pays its one-time costs (its memory faulted
  // in, the other side's kernels and corona lines made): in the demo 0.4-0.6 s where later trials
  // like it take 0.1 s, more than the first trial's half second, so the second onset waited for
  // them. Before the first flip nothing is shown yet: the wait only delays the session's start.
  // (Where the first trial's own frames are still being made, the next is begun after its flips.)
  if (first_of_run && clock_.keeps_real_time() && !fast_forward_ && !streaming_) {
    begin_trial_ahead(plan, schedule, 0, clock_.now_s() + period_s_, intervals);
    if (!ahead_.empty() && ahead_.front()->worker.joinable()) ahead_.front()->worker.join();
  }
  if (!run_timed_sequence(plan, schedule, intervals, question, run)) return false;
  finish_stream();  // every frame was shown: the worker has made its last one
  const auto report_start = std::chrono::steady_clock::now();
  for (const IntervalGlare& interval_glare : intervals.glare) glare_.report_interval(plan, interval_glare);
  log_trial_preparation(plan, intervals);
  timing_.add_work(FlipWork::recording, seconds_since(report_start));  // the events written

  if (!collect_response(plan, question, run)) return false;
  // The answer is in: scored now, shown as feedback, then committed with every flip. An abort
  // during the feedback still commits the answered trial.
  const TrialOutcome outcome = prepared_.procedure->record_response(plan, *run.response);
  const std::string feedback = feedback_text(outcome);
  if (!feedback.empty())
    present_timed_blank(plan, run, FlipPhase::feedback, presentation.feedback_duration.frames,
                        overlays_.centred_text(feedback));
  // The commit goes on beside the next trial's start (trial_commit.cpp): handing it over is this
  // thread's part of recording the trial.
  const auto record_start = std::chrono::steady_clock::now();
  // A trial is committed with its saved frames on disk (written beside its flips and its answer,
  // saved_frame_writer.h): a frame that cannot be written ends the session before its trial is.
  if (frame_writer_) frame_writer_->finish();
  const int total = prepared_.procedure->planned_trials();
  const bool says_progress = total >= 50 && (plan.trial_index + 1) % (total / 10) == 0;
  commit(plan, run, outcome,
         says_progress ? "  trial " + std::to_string(plan.trial_index + 1) + "/" + std::to_string(total) + "\n" : "",
         progress);
  timing_.add_work(FlipWork::recording, seconds_since(record_start));
  if (aborted_) return false;
  return true;
}

// Glare frame k of an interval is computed for the time it will flip. Returns false when the
// session was interrupted while the frames were prepared.
bool SessionLoop::begin_intervals(const TrialPlan& plan, const TrialSchedule& schedule, int flips_after,
                                  bool prepare_in_interval, TrialIntervals& intervals) {
  for (int interval = 0; interval < schedule.intervals; ++interval) {
    const TrialPlan& shown = intervals.shown_plans.emplace_back(interval_plan(plan, interval));
    std::size_t first_flip = 0;
    while (schedule.timed[first_flip].interval != interval) ++first_flip;
    if (shown.straylight) {  // the ring and the compensation light (straylight_trial.cpp)
      intervals.placements.push_back(straylight_frame(shown, 0));
      intervals.stimulus_rects.push_back(straylight_rect_);
      intervals.glare.push_back(begin_straylight(shown, static_cast<int>(first_flip) + flips_after));
      continue;
    }
    if (!shown.real_stimulus.empty()) {
      // A physical object: the instruction to look at it (below) instead of an image.
      intervals.placements.emplace_back();
      intervals.glare.push_back(begin_real_stimulus(shown, static_cast<int>(first_flip) + flips_after));
      continue;
    }
    intervals.placements.push_back(layout(shown));
    for (const Placement& placement : intervals.placements.back()) intervals.stimulus_rects.push_back(placement.rect);
    intervals.glare.push_back(
        glare_.begin_interval(shown, intervals.placements.back(), static_cast<int>(first_flip) + flips_after));
    const auto interrupted = [this] {
      check_interrupt();
      return aborted_;
    };
    const auto work_start = std::chrono::steady_clock::now();
    const std::size_t frames_before = intervals.glare.back().frames.size();
    if (glare_.prepared_before_onset(intervals.glare.back())) {
      if (status_) status_->set_detail("preparing glare frames");
      glare_.prepare_frames(intervals.glare.back(), interrupted);
      if (status_) status_->set_detail("");
    } else if (prepare_in_interval) {
      // A live interval's first frame is computed in the inter-trial interval too (without a
      // tracker a frame is a function of its time): the onset flip, which also composes the
      // scenes, then only draws, and comes on time.
      glare_.compute_frame(intervals.glare.back(), 0);
    }
    timing_.add_work(work_kind(intervals.glare.back()), seconds_since(work_start));
    preparation_.onset_frames_computed += static_cast<int>(intervals.glare.back().frames.size() - frames_before);
    if (aborted_) return false;  // Ctrl-C or SIGTERM while the glare frames were prepared
  }
  return true;
}

bool SessionLoop::run_timed_sequence(const TrialPlan& plan, const TrialSchedule& schedule, TrialIntervals& intervals,
                                     const std::vector<Placement>& question, TrialRun& run) {
  const bool interactive = prepared_.observer == nullptr;
  // The timed sequence: fixation, interval 1 [, inter-stimulus interval, interval 2].
  double sequence_start_s = 0.0;
  for (std::size_t i = 0; i < schedule.timed.size(); ++i) {
    const TimedFlip& flip = schedule.timed[i];
    // Fixation and inter-stimulus flips repeat the frame before them: only its encoding is redrawn.
    const bool repeated = i > 0 && flip.phase != FlipPhase::interval && schedule.timed[i - 1].phase == flip.phase;
    if (repeated) {
      encode();
    } else if (flip.phase == FlipPhase::fixation) {
      draw({}, nullptr, overlays_.fixation());
    } else if (flip.phase == FlipPhase::interval) {
      IntervalGlare& shown_glare = intervals.glare[static_cast<std::size_t>(flip.interval)];
      // Live: this frame's glare now, with the gaze of this moment (nothing when already there);
      // or the frame the worker still making the trial's frames has made (waited for).
      const auto compute_start = std::chrono::steady_clock::now();
      const GlaredRegion* region = nullptr;
      if (!streamed_frame(flip.interval, flip.frame_in_interval, region)) {
        const std::size_t frames_before = shown_glare.frames.size();
        glare_.compute_frame(shown_glare, flip.frame_in_interval);
        if (flip.stimulus_frame == 0)
          preparation_.onset_frames_computed += static_cast<int>(shown_glare.frames.size() - frames_before);
        region = shown_glare.shown(flip.frame_in_interval);
      }
      timing_.add_work(work_kind(shown_glare), seconds_since(compute_start));
      // Until the presentation is settled, each computed flip's drawing is timed (with its GL work
      // finished): with the frame's own cost it is what a live frame takes.
      const bool timed = shown_glare.computed() && shown_glare.frames_needed > 1 &&
                         !glare_.presentation_settled(shown_glare);
      const auto draw_start = std::chrono::steady_clock::now();
      draw(plan.straylight ? straylight_frame(plan, flip.frame_in_interval)
                           : intervals.placements[static_cast<std::size_t>(flip.interval)],
           region, question);
      timing_.add_work(FlipWork::drawing, seconds_since(draw_start));
      if (timed && !fast_forward_) {
        renderer_.finish();
        shown_glare.frame_draw_s.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - draw_start).count());
      }
      save_straylight_cycle_frame(plan, flip.frame_in_interval);
      if (flip.frame_in_interval == 0 &&
          capture_first_frame(intervals.shown_plans[static_cast<std::size_t>(flip.interval)], flip.interval)) {
        aborted_ = true;
        abort_reason_ = "preview captured";
        return false;
      }
    } else {
      draw({}, nullptr, question);
    }
    const double flip_s = present();
    if (flip.phase == FlipPhase::interval && flip.frame_in_interval == 0)
      save_first_frame(intervals.shown_plans[static_cast<std::size_t>(flip.interval)], flip.interval);
    after_flip(flip_s);
    if (i == 0) sequence_start_s = flip_s;
    if (i == schedule.onset_flip) run.onset_s = flip_s;
    const double scheduled_s = sequence_start_s + static_cast<double>(i) * period_s_;
    if (flip.stimulus_frame >= 0) {
      // A flip more than 1.5 refresh periods after the previous one means a refresh was missed.
      const bool dropped = timing_.on_flip(flip_s, plan.trial_index, flip.stimulus_frame);
      if (dropped)
        log_late_flip(plan, flip_s, "frame " + std::to_string(flip.stimulus_frame), timing_.dropped().back().interval_s);
      if (const std::optional<LateOnset>& late = timing_.late_onset()) log_late_onset(plan, flip_s, *late);
      IntervalGlare& shown_glare = intervals.glare[static_cast<std::size_t>(flip.interval)];
      // A live glare frame that came late: "auto" takes its layout back to prepared frames.
      if (glare_.shown_live(shown_glare)) {
        ++shown_glare.live_frames_shown;
        if (dropped) ++shown_glare.live_frames_dropped;
      }
      // Live glare with a tracker: how old this frame's gaze was when it flipped (never a trial
      // whose worker still makes its frames: no tracker runs then).
      std::optional<double> gaze_age_s;
      const std::optional<double> gaze_time_s =
          streaming_ ? std::nullopt : shown_glare.gaze_time_of(flip.frame_in_interval);
      if (gaze_time_s) {
        gaze_age_s = flip_s - *gaze_time_s;
        shown_glare.gaze_to_flip_s.push_back(*gaze_age_s);
      }
      record_flip(run, {flip.phase, flip.interval, flip.stimulus_frame}, scheduled_s, flip_s, dropped, gaze_age_s);
      // The next trial laid out and its frames begun on a worker once none of this one's is left
      // to compute (after the onset for prepared frames): not during a preview's fast-forward.
      if (!ahead_begun_ && !fast_forward_) begin_trial_ahead(plan, schedule, i, flip_s, intervals);
    } else {
      const std::optional<double> late_s = timing_.on_timed_flip(flip_s);
      if (late_s) log_late_flip(plan, flip_s, std::string(to_string(flip.phase)) + " flip", *late_s);
      record_flip(run, {flip.phase, -1, -1}, scheduled_s, flip_s, late_s.has_value());
    }
    if (i == schedule.first_answer_flip) run.answers_from_s = flip_s;
    if (interactive && i >= schedule.first_answer_flip && !run.response) {
      std::optional<Response> answer = poll_keyboard(plan, run.onset_s, run.answers_from_s);
      if (answer) finish_commit();  // the trial before is in before this answer counts
      run.response = std::move(answer);
    }
    else if (interactive)
      ignore_keys(plan, run.response                       ? "came after the answer"
                        : flip.phase == FlipPhase::fixation ? "pressed before onset"
                                                            : "pressed before the second interval's onset");
    else
      check_interrupt();
    if (aborted_) return false;
  }
  return true;
}

bool SessionLoop::collect_response(const TrialPlan& plan, const std::vector<Placement>& question, TrialRun& run) {
  // The trial before is committed before this one's answer is taken (trial_commit.cpp).
  finish_commit();
  const bool interactive = prepared_.observer == nullptr;
  const double window_s = prepared_.experiment.presentation.response_window_s;
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
      const double flip_s = present();
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

  return true;
}

void SessionLoop::save_first_frame(const TrialPlan& plan, int interval) {
  if (save_frames_dir_.empty() || fast_forward_) return;
  char name[64];
  std::snprintf(name, sizeof name, interval == 0 ? "trial_%04d.exr" : "trial_%04d_interval_%d.exr", plan.trial_index,
                interval + 1);
  // Written so that it loads as a scene with no option (glare round-off below 0 set to 0),
  // compressed and written on the writer's thread: the read-back and any wait for the writer are
  // the session's own work before the next flip (recording).
  const auto saving_start = std::chrono::steady_clock::now();
  frame_writer_->write((std::filesystem::path(save_frames_dir_) / name).string(), renderer_.read_stimulus(),
                       /*as_scene=*/true);
  timing_.add_work(FlipWork::recording, seconds_since(saving_start));
}

bool SessionLoop::capture_first_frame(const TrialPlan& plan, int interval) {
  if (!capture_.captures(plan) || interval != 0 || !capture_.frame) return false;
  capture_.frame->stimulus_cd_m2 = renderer_.read_stimulus();
  capture_.frame->display_drive = renderer_.read_display();
  capture_.captured.push_back(std::move(*capture_.frame));
  capture_.frame.reset();
  // The session ends once every condition asked for is captured; until then it runs on as it would.
  return capture_.complete();
}

std::string SessionLoop::feedback_text(const TrialOutcome& outcome) const {
  const PresentationSpec& presentation = prepared_.experiment.presentation;
  if (presentation.feedback == FeedbackKind::none) return "";
  if (outcome.response == kTimeoutResponse) return presentation.feedback_timeout_text;
  if (!outcome.correct) return "";
  return *outcome.correct == 1 ? presentation.feedback_correct_text : presentation.feedback_wrong_text;
}

}  // namespace glarelab
