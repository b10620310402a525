#pragma once
// The headset's own eye tracker as the session's tracker (docs/STEREO.md, "Eye gaze"): the gaze the
// OpenXR display locates at each submitted frame (runner/display/headset_gaze.h) becomes one
// TrackerSample per eye at the frame's predicted display time, normalised in that eye's view, as a
// head-mounted tracker reports gaze. From there it goes where any tracker's samples go: the
// TrackerSession (glare and adaptation at each eye's own gaze), the TrackerLogger (tracker_samples).
//  - Eye ids are the trackers' (0 right, 1 left): eye 0 is the right view's point, eye 1 the left's.
//  - No pupil: OpenXR reports none. Each sample's diameter is 0 (stored as NULL), which the pupil
//    filter never accepts, so the glare's pupil stays each eye model's own (Eq. 1-2 at the adapting
//    luminance) even with [glare] pupil_source = "tracker".
//  - A frame whose gaze the runtime could not locate (no valid orientation) gives no sample: the
//    first such frame is a `tracker_lost` event, the first located one after it a
//    `tracker_reconnected`, as a tracker's dropout is logged; never a gaze of (0, 0).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "runner/display/headset_gaze.h"
#include "runner/tracker/tracker_source.h"

namespace glarelab {

class PredictedFlipClock;

class HeadsetGazeTracker final : public TrackerSource {
 public:
  // `display` must outlive start() to stop(): stop() takes what the display kept and lets it go, and
  // nothing touches the display afterwards (the session stops its tracker before the display
  // closes: TrackerSourceStopper).
  explicit HeadsetGazeTracker(HeadsetGazeSource& display);
  // The clock must be the predicted-flip clock of the OpenXR display (TrackerError otherwise).
  void start(const SessionClock& clock) override;
  void stop() override;
  // Every frame's gaze since the last call (the frames submitted up to now, or up to stop()).
  TrackerBatch poll(double now_s) override;
  bool live() const override { return true; }
  TrackerStatus status() const override { return status_; }
  std::string description() const override;

 private:
  HeadsetGazeSource& display_;
  const PredictedFlipClock* clock_ = nullptr;
  bool running_ = false;
  std::vector<HeadsetGazeSample> taken_at_stop_;
  TrackerStatus status_;
  bool lost_ = false;
  double lost_since_s_ = 0.0;
  std::optional<double> last_tracked_s_;
};

}  // namespace glarelab
