// The next trial prepared while the current one runs (docs/TIMING.md, "Trials prepared ahead").
// Without it a trial's glare frames are computed after the previous trial's answer, so on a CPU the
// onset waits for them (the demo's dynamic glare: about 30 frames of 50-100 ms on two cores). When
// the procedure knows the next trial before the answer (Procedure::peek_following_trial: the fixed
// designs), the display's thread lays it out right after a stimulus flip of the current trial, and a
// worker thread composes its scenes on the CPU (runner/session/cpu_composition.h), begins its glare
// and computes its frames beside the remaining flips, the answer and the next inter-trial interval. The
// onset then takes its frames without computing any; a worker not done by then is waited for, and
// that wait is the onset's glare preparation (runner/session/frame_timing.h).
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "core/clock.h"
#include "core/number_text.h"
#include "runner/session/session_loop.h"

namespace glarelab {
namespace {

// The worker runs below the display's thread so a flip is never queued behind a frame's glare on
// a busy machine, and ahead of background jobs: at a niceness of 2 (CFS weight 655 against the
// display thread's 1024) it has twice the share of a build at niceness 5 (335); at 5 it had the
// same, and on two cores with a build beside it a dynamic trial's frames took it twice as long.
constexpr int kWorkerNiceness = 2;

std::string ms_text(double seconds) { return number_text(std::round(seconds * 1e4) / 10.0); }

// Whether two plans show the same trial: what the frames are made of (scenes, their scales and
// places, the condition, each side's glare) and its length.
bool same_trial(const TrialPlan& a, const TrialPlan& b) {
  return a.trial_index == b.trial_index && a.block == b.block && a.condition_name == b.condition_name &&
         a.condition_json == b.condition_json && a.positions == b.positions && a.scenes == b.scenes &&
         a.scene_scale == b.scene_scale && a.position_glare == b.position_glare &&
         a.glare_keeps_peak == b.glare_keeps_peak && a.real_stimulus == b.real_stimulus &&
         a.stimulus_frames == b.stimulus_frames && a.screen_text == b.screen_text;
}

// The feedback flips a trial will show after its answer when the answer is scored (a right answer
// exists): the prediction of the next onset assumes it, as it assumes an answer at once.
int predicted_feedback_flips(const PresentationSpec& presentation, const TrialPlan& plan) {
  return presentation.feedback != FeedbackKind::none && !plan.correct_response.empty()
             ? presentation.feedback_duration.frames
             : 0;
}

// The frames the worker computes for an interval: all of them, live or prepared alike. A trial is
// prepared ahead only without a tracker, where a live frame, computed just before its flip, is the
// frame prepared for that flip (dynamic glare is a function of time and seed, glare_presentation.cpp):
// so the display's thread computes no glare for it at all, and a live interval's flips only draw.
int frames_ahead(const IntervalGlare& glare) { return glare.computed() ? -1 : 0; }

}  // namespace

SessionLoop::~SessionLoop() {
  // Every worker stopped first: a worker prepared ahead waits for the one before it.
  if (streaming_) streaming_->stop = true;
  drop_trial_ahead();
  if (streaming_ && streaming_->worker.joinable()) streaming_->worker.join();
  // A session ended by an error: the answered trial's commit still lands (its own error, if any,
  // is the lesser one and is not thrown from here).
  if (committer_.joinable()) committer_.join();
}

void SessionLoop::drop_trial_ahead() {
  for (const std::unique_ptr<TrialAhead>& ahead : ahead_) ahead->stop = true;
  for (const std::unique_ptr<TrialAhead>& ahead : ahead_)
    if (ahead->worker.joinable()) ahead->worker.join();
  ahead_.clear();
}

void SessionLoop::begin_trial_ahead(const TrialPlan& current, const TrialSchedule& schedule, std::size_t flip,
                                    double flip_s, const TrialIntervals& shown) {
  if (streaming_ && streaming_->stream.complete()) finish_stream();
  // Only once none of the current trial's frames is left to compute on this thread: the eyes'
  // engines are then the workers' alone until the next trial takes its frames. (A trial whose
  // worker still makes its frames has none computed here; the next worker waits for that one.)
  if (!streaming_)
    for (const IntervalGlare& glare : shown.glare)
      if (glare.computed() && static_cast<int>(glare.frames.size()) < glare.frames_needed) return;
  const int feedback_flips = predicted_feedback_flips(prepared_.experiment.presentation, current);
  if (ahead_.empty()) {
    const std::optional<TrialPlan> next = prepared_.procedure->peek_following_trial();
    std::optional<TrialSchedule> next_schedule;
    if (next) next_schedule = schedule_trial(prepared_.experiment.presentation, *next, sequential_);
    // Where the worker composes the next trial's scenes (every one shown at its own size,
    // CpuComposition::exact), this thread only lays it out: microseconds, begun at once after this
    // flip. Where GL must compose them here, that takes milliseconds (the scenes composed and read
    // back: 5 to 90 ms on two loaded cores with llvmpipe), too long to fit beside a stimulus flip's
    // own drawing in one period, and it needs the eyes' engines no worker holds. When flips that
    // are not stimulus frames follow this trial's last one (an answer awaited from a person,
    // feedback, the next inter-trial interval or fixation), it is done after that last stimulus
    // flip, delaying at most one of those; when the next onset follows directly, after this flip,
    // so that the worker has the trial's remaining flips. (A physical object has no scene to lay
    // out; it is declined below.)
    bool composed_here = false;
    for (int interval = 0; next && next->real_stimulus.empty() && interval < next_schedule->intervals; ++interval)
      composed_here = composed_here || !composition_.exact(layout(interval_plan(*next, interval)));
    std::size_t last_stimulus = 0;
    for (std::size_t i = 0; i < schedule.timed.size(); ++i)
      if (schedule.timed[i].stimulus_frame >= 0) last_stimulus = i;
    const bool last_stimulus_flip = flip == last_stimulus;
    const bool flips_follow = prepared_.observer == nullptr || feedback_flips > 0 || last_stimulus + 1 < schedule.timed.size() ||
                              (next_schedule && (next_schedule->inter_trial_frames > 0 || next_schedule->onset_flip > 0));
    if (composed_here && (streaming_ || (flips_follow && !last_stimulus_flip))) return;
    ahead_begun_ = true;
    next_not_ahead_ = why_not_ahead(next ? &*next : nullptr, next ? &*next_schedule : nullptr);
    if (!next_not_ahead_.empty()) return;
    // Frame k of an interval is computed for the flip it is planned for (trial_glare.cpp): here the
    // current trial's remaining timed flips, the answer at once, its feedback when scored, the next
    // trial's inter-trial interval and its flips before the interval; one period later than that
    // flip, as the interval's glare begun at the trial would place it (SessionGlare::begin_interval,
    // timed from the clock's next flip).
    const int flips_to_next =
        static_cast<int>(schedule.timed.size() - 1 - flip) + feedback_flips + next_schedule->inter_trial_frames;
    begin_one_trial_ahead(*next, *next_schedule, flip_s + (flips_to_next + 1) * period_s_, current.trial_index,
                          /*may_compose_in_gl=*/true);
  }
  ahead_begun_ = true;
  // The trials after it, each taken where the one before it ends (its timed flips, the answer at
  // once, its feedback, the next inter-trial interval): declined silently here, a trial not begun
  // now is the next one when the trial before it runs.
  while (ahead_.size() < kTrialsAhead) {
    const std::optional<TrialPlan> next = prepared_.procedure->peek_following_trial(ahead_.size());
    if (!next) return;
    const TrialSchedule next_schedule = schedule_trial(prepared_.experiment.presentation, *next, sequential_);
    if (!why_not_ahead(&*next, &next_schedule).empty()) return;
    const TrialAhead& before = *ahead_.back();
    const double start_s =
        before.start_s +
        (static_cast<double>(before.timed_flips) + before.feedback_flips + next_schedule.inter_trial_frames) * period_s_;
    // Not where GL would compose its scenes here: a worker holds the eyes' engines.
    if (!begin_one_trial_ahead(*next, next_schedule, start_s, current.trial_index, /*may_compose_in_gl=*/false)) return;
  }
}

std::string SessionLoop::why_not_ahead(const TrialPlan* plan, const TrialSchedule* plan_schedule) {
  if (capture_.preview != nullptr) return "a preview runs the session";
  if (tracker_.active()) return "a tracker gives the gaze, taken as late as it can be";
  if (plan == nullptr) return "the procedure places it by the answer before it";
  if (!plan->real_stimulus.empty()) return "it shows a physical object";
  if (!plan_schedule->screens.empty()) return "a screen comes before it";
  // Asked before the trial's glare is begun (begin_interval shows an adapting eye its frame).
  if (!glare_.computes_off_display_thread()) return "the GL engine computes its frames";
  return {};
}

bool SessionLoop::begin_one_trial_ahead(const TrialPlan& plan, const TrialSchedule& plan_schedule, double start_s,
                                        int beside, bool may_compose_in_gl) {
  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t writes_before = renderer_.stimulus_generation();
  auto ahead = std::make_unique<TrialAhead>();
  ahead->plan = plan;
  ahead->beside_trial = beside;
  ahead->start_s = start_s;
  ahead->timed_flips = plan_schedule.timed.size();
  ahead->feedback_flips = predicted_feedback_flips(prepared_.experiment.presentation, plan);
  bool exact = true;
  for (int interval = 0; interval < plan_schedule.intervals; ++interval) {
    const TrialPlan& shown = ahead->intervals.shown_plans.emplace_back(interval_plan(plan, interval));
    std::size_t first_flip = 0;
    while (plan_schedule.timed[first_flip].interval != interval) ++first_flip;
    ahead->intervals.placements.push_back(layout(shown));
    for (const Placement& placement : ahead->intervals.placements.back())
      ahead->intervals.stimulus_rects.push_back(placement.rect);
    ahead->first_flip_s.push_back(start_s + (1.0 + static_cast<double>(first_flip)) * period_s_);
    exact = exact && composition_.exact(ahead->intervals.placements.back());
  }
  if (!exact && !may_compose_in_gl) return false;
  // Composing the scenes in GL (and reading them back) took this thread 14 to 560 ms under load, a
  // dropped frame per trial: the worker composes them on the CPU, GL's frame bit for bit, where
  // every scene is shown at its own size. A scaled one is composed in GL here, as before (only for
  // the next trial, with no worker running: begin_trial_ahead).
  ahead->composed_on_worker = exact;
  bool computes = exact;
  if (!exact) {
    for (std::size_t i = 0; i < ahead->intervals.shown_plans.size(); ++i) {
      IntervalGlare& glare = ahead->intervals.glare.emplace_back(
          glare_.begin_interval(ahead->intervals.shown_plans[i], ahead->intervals.placements[i], 0));
      glare.first_flip_s = ahead->first_flip_s[i];
      ahead->frames_to_compute.push_back(frames_ahead(glare));
      computes = computes || ahead->frames_to_compute.back() != 0;
    }
  }
  ahead->layout_s = seconds_since(start);
  ahead->display_writes = renderer_.stimulus_generation() - writes_before;
  timing_.add_work(FlipWork::glare_preparation, ahead->layout_s);
  TrialAhead* const a = ahead_.emplace_back(std::move(ahead)).get();
  if (!computes) {
    a->worker_done.set_value();
    return true;
  }
  // Below the display's thread where flips keep real time. On the virtual clock no flip waits for
  // it, while the display's thread flips as fast as it draws: at a lower priority the worker's
  // frames (and its helper threads', core/chunk_pool.h) would measure the costs by which "auto"
  // settles a glare layout (glare_presentation.cpp) as those of a starved thread.
  const bool below_display = clock_.keeps_real_time();
  const std::shared_future<void> worker_before = last_worker_done_;
  last_worker_done_ = a->worker_done.get_future().share();
  a->worker = std::thread([this, a, below_display, worker_before] {
    if (below_display)
      setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), kWorkerNiceness);  // best effort
    if (worker_before.valid()) worker_before.wait();  // the eyes' engines are one worker's at a time
    const auto worker_start = std::chrono::steady_clock::now();
    try {
      make_frames_ahead(*a);
    } catch (...) {
      a->error = std::current_exception();
    }
    a->worker_s = seconds_since(worker_start);
    a->stream.finish();
    a->worker_done.set_value();
  });
  return true;
}

void SessionLoop::make_frames_ahead(TrialAhead& ahead) {
  for (std::size_t i = 0; ahead.composed_on_worker && i < ahead.intervals.shown_plans.size() && !ahead.stop; ++i) {
    const IntervalGlare& glare = ahead.intervals.glare.emplace_back(glare_.begin_interval_off_display(
        ahead.intervals.shown_plans[i], ahead.intervals.placements[i], ahead.first_flip_s[i], composition_));
    ahead.frames_to_compute.push_back(frames_ahead(glare));
  }
  // Each frame's place is reserved before the first, so a frame published stays where it is
  // while the display's thread shows it; from begin() on, the intervals may be moved into the
  // trial (the vector's elements stay in place), and only these pointers reach them.
  std::vector<IntervalGlare*> glares;
  std::vector<int> counts;
  for (std::size_t i = 0; i < ahead.intervals.glare.size(); ++i) {
    IntervalGlare& glare = ahead.intervals.glare[i];
    const int needed = glare.computed() ? glare.frames_needed : 0;
    counts.push_back(ahead.frames_to_compute[i] < 0 ? needed : std::min(needed, ahead.frames_to_compute[i]));
    glare.frames.reserve(static_cast<std::size_t>(glare.frames_needed));
    glares.push_back(&glare);
  }
  ahead.stream.begin(counts);
  const auto stopped = [&ahead] { return ahead.stop.load(); };
  for (std::size_t i = 0; i < glares.size(); ++i) {
    for (int k = 0; k < counts[i] && !ahead.stop; ++k) {
      IntervalGlare& glare = *glares[i];
      const std::size_t before = glare.frames.size();
      glare_.prepare_frames(glare, stopped, k + 1, /*display_thread=*/false);
      if (glare.frames.size() <= static_cast<std::size_t>(k)) break;
      ahead.frames += static_cast<int>(glare.frames.size() - before);
      ahead.stream.publish(static_cast<int>(i), k, &glare.frames[static_cast<std::size_t>(k)],
                           glare.frame_compute_s.empty() ? 0.0 : glare.frame_compute_s.back());
    }
  }
}

bool SessionLoop::trial_ahead_matches(const TrialPlan& plan) const {
  return !ahead_.empty() && same_trial(ahead_.front()->plan, plan);
}

bool SessionLoop::take_trial_ahead(const TrialPlan& plan, const TrialSchedule& schedule, TrialIntervals& intervals) {
  if (!trial_ahead_matches(plan)) {
    if (!ahead_.empty()) preparation_.not_ahead = "the trial shown is not the one prepared";
    drop_trial_ahead();
    return false;
  }
  TrialAhead& ahead = *ahead_.front();
  // On the virtual clock each frame must be the one preparing it now would make (a session's
  // frames do not depend on how they were prepared): frames timed for other flips (a longer answer
  // or no feedback) are prepared again. On a real clock the flips are the planned ones either way.
  if (!clock_.keeps_real_time()) {
    for (std::size_t i = 0; i < ahead.first_flip_s.size(); ++i) {
      std::size_t first_flip = 0;
      while (schedule.timed[first_flip].interval != static_cast<int>(i)) ++first_flip;
      const double planned_s = clock_.now_s() + (1.0 + static_cast<double>(first_flip)) * period_s_;
      if (std::abs(ahead.first_flip_s[i] - planned_s) > 1e-9) {
        preparation_.not_ahead = "its frames were timed for other flips than it shows";
        drop_trial_ahead();
        return false;
      }
    }
  }
  // The onset waits until the frames still to make can follow its flips (FrameStream), or for the
  // worker to be done; what it has not made by then it makes while the interval is shown.
  const auto wait_start = std::chrono::steady_clock::now();
  const bool working = ahead.worker.joinable();
  if (working) ahead.stream.wait_until_onset_fits(period_s_);
  // Every frame there: the worker is at its end, and is joined.
  const bool streams = working && !ahead.stream.finished() && !ahead.stream.complete();
  if (working && !streams) ahead.worker.join();
  const double wait_s = seconds_since(wait_start);
  timing_.add_work(FlipWork::glare_preparation, wait_s);
  if (!streams && ahead.error) {
    const std::exception_ptr error = ahead.error;
    drop_trial_ahead();
    std::rethrow_exception(error);
  }
  preparation_.ahead = true;
  preparation_.not_ahead.clear();
  preparation_.beside_trial = ahead.beside_trial;
  if (!streams) {  // else counted when the worker is done (finish_stream)
    preparation_.worker_frames = ahead.frames;
    preparation_.worker_s = ahead.worker_s;
  }
  preparation_.layout_ms = 1e3 * ahead.layout_s;
  preparation_.composed_on_worker = ahead.composed_on_worker;
  preparation_.display_writes = ahead.display_writes;
  preparation_.onset_wait_s = wait_s;
  preparation_.ready_at_onset = streams ? ahead.stream.ready() : -1;
  // The intervals move into the trial; their elements stay where the worker makes their frames.
  intervals = std::move(ahead.intervals);
  std::unique_ptr<TrialAhead> taken = std::move(ahead_.front());
  ahead_.pop_front();
  if (streams) streaming_ = std::move(taken);
  return true;
}

bool SessionLoop::streamed_frame(int interval, int k, const GlaredRegion*& frame) {
  if (!streaming_) return false;
  const auto wait_start = std::chrono::steady_clock::now();
  const bool there = streaming_->stream.wait_for(interval, k, frame);
  preparation_.flip_wait_s += seconds_since(wait_start);
  if (there) return true;
  // Stopped or failed without it: its error thrown; else the interval's own frames from here on.
  finish_stream();
  return false;
}

void SessionLoop::finish_stream(bool stop) {
  if (!streaming_) return;
  if (stop) streaming_->stop = true;
  if (streaming_->worker.joinable()) streaming_->worker.join();
  const std::unique_ptr<TrialAhead> done = std::move(streaming_);
  if (done->error && !stop) std::rethrow_exception(done->error);
  preparation_.worker_frames = done->frames;
  preparation_.worker_s = done->worker_s;
}

void SessionLoop::log_trial_preparation(const TrialPlan& plan, const TrialIntervals& intervals) {
  bool computed = false;
  for (const IntervalGlare& glare : intervals.glare) computed = computed || glare.computed();
  if (!computed) return;
  std::string text = "trial " + std::to_string(plan.trial_index) + ": ";
  if (preparation_.ahead) {
    text += "frames prepared ahead beside trial " + std::to_string(preparation_.beside_trial) + " (" +
            std::to_string(preparation_.worker_frames) + " glare frame(s) on a worker in " +
            ms_text(preparation_.worker_s) + " ms, its scenes composed " +
            (preparation_.composed_on_worker ? "there on the CPU" : "in GL on the display's thread") + "; laid out in " +
            number_text(std::round(preparation_.layout_ms * 10) / 10) + " ms on the display's thread, " +
            std::to_string(preparation_.display_writes) +
            " write(s) to the stimulus framebuffer); the onset waited " + ms_text(preparation_.onset_wait_s) + " ms for them";
    if (preparation_.ready_at_onset >= 0)
      text += " (" + std::to_string(preparation_.ready_at_onset) +
              " of them made by then, the rest while the interval was shown: its flips waited " +
              ms_text(preparation_.flip_wait_s) + " ms for them)";
  } else {
    text += "frames prepared at the trial, not ahead: " +
            (preparation_.not_ahead.empty() ? std::string("the first trial of the run") : preparation_.not_ahead);
  }
  text += "; glare frames computed on the display's thread for the onset: " + std::to_string(preparation_.onset_frames_computed);
  // Written with the trial's commit, beside the next onset (trial_commit.cpp): a synced write here
  // would sit between this trial's last flip and the next onset.
  events_with_commit_.push_back({clock_.now_s(), "trial_preparation", std::move(text)});
}

}  // namespace glarelab
