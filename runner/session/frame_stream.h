#pragma once
// A trial's glare frames handed from the worker that makes them (runner/session/trial_ahead.cpp) to
// the display's thread that shows them, frame by frame (docs/TIMING.md, "Trials prepared ahead").
// A dynamic interval's 30 frames on two cores can take longer than the trial before leaves: the
// onset then waits only until the frames still to make can follow the flips that show them, and
// the worker goes on making them in order while the interval is shown; each flip takes its frame
// when it is there, waiting for it when it is not (a flip that waits past its refresh is dropped,
// and logged so, as any other).
#include <condition_variable>
#include <mutex>
#include <vector>

#include "runner/session/glared_region.h"

namespace glarelab {

class FrameStream {
 public:
  // --- the worker's side ---
  // Before the first frame: how many frames each interval will have (0: none computed). From here
  // on the worker touches the intervals' glare only through the frames it publishes.
  void begin(const std::vector<int>& frames_per_interval);
  // Frame `k` of `interval`, made in order; it stays where it is (the worker reserved every frame's
  // place before the first), and is never written again. `compute_s`: the wall time it took.
  void publish(int interval, int k, const GlaredRegion* frame, double compute_s);
  // The worker is done: every frame published, or stopped, or failed.
  void finish();

  // --- the display's side ---
  // Waits until the frames not yet made can be made before the flips that show them, each flip
  // one refresh period after the onset's (`period_s`), or the worker is done: at least the first
  // kLeadFrames of them ready, and, at the worker's measured pace (the mean of the frames made so
  // far after each interval's first, which also prepares the interval's composed frame) with a
  // margin of kPaceMargin, the last frame due half a period before its flip. All of them when the
  // pace is not known yet (fewer than kPacedFrames frames after an interval's first).
  void wait_until_onset_fits(double period_s);
  // Frame `k` of `interval` (its last one when the interval has fewer: a frame serving the whole
  // interval), waiting for it. `frame` is set to it, or to nullptr when the interval computes no
  // frame. False when the worker finished without it (stopped or failed).
  bool wait_for(int interval, int k, const GlaredRegion*& frame);
  // Frames published before the onset (its call of wait_until_onset_fits), and the frames in all.
  int ready() const;
  int total() const;
  bool complete() const;  // every frame published
  bool finished() const;  // finish() was called

  static constexpr int kLeadFrames = 3;
  static constexpr int kPacedFrames = 4;
  // Twice the pace: the worker's frames slow once the interval's flips draw beside it (a margin of
  // 1.5 left the demo's first dynamic trial's flips waiting 674 ms in one run at load 3).
  static constexpr double kPaceMargin = 2.0;
  // The rule wait_until_onset_fits waits for: `made` of `total` frames there, the worker's mean
  // time per frame `mean_frame_s` (0: not known yet), a refresh period of `period_s`.
  static bool onset_fits(int made, int total, double mean_frame_s, double period_s);

 private:
  bool onset_fits_now(double period_s) const;  // mutex_ held
  int published_total() const;                 // mutex_ held: frames published over all intervals
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool begun_ = false, finished_ = false;
  std::vector<std::vector<const GlaredRegion*>> frames_;  // per interval, in order; nullptr until published
  std::vector<int> published_;                            // per interval
  double paced_s_ = 0.0;  // the compute time of the frames after each interval's first
  int paced_frames_ = 0;
  int total_ = 0, ready_ = 0;
};

}  // namespace glarelab
