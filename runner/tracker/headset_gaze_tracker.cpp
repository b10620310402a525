#include "runner/tracker/headset_gaze_tracker.h"

#include <algorithm>
#include <utility>

#include "core/number_text.h"
#include "runner/display/openxr_clock.h"

namespace glarelab {

HeadsetGazeTracker::HeadsetGazeTracker(HeadsetGazeSource& display) : display_(display) {}

void HeadsetGazeTracker::start(const SessionClock& clock) {
  clock_ = dynamic_cast<const PredictedFlipClock*>(&clock);
  if (clock_ == nullptr)
    throw TrackerError("the headset's eye gaze is stamped with the OpenXR display's predicted display times; the "
                       "session clock is '" + clock.name() + "'");
  display_.keep_eye_gaze(true);
  running_ = true;
}

void HeadsetGazeTracker::stop() {
  if (!running_) return;
  running_ = false;
  for (HeadsetGazeSample& gaze : display_.take_eye_gaze()) taken_at_stop_.push_back(gaze);
  display_.keep_eye_gaze(false);
}

TrackerBatch HeadsetGazeTracker::poll(double) {
  TrackerBatch batch;
  if (clock_ == nullptr) return batch;
  std::vector<HeadsetGazeSample> frames = std::exchange(taken_at_stop_, {});
  if (running_)
    for (HeadsetGazeSample& gaze : display_.take_eye_gaze()) frames.push_back(gaze);
  for (const HeadsetGazeSample& gaze : frames) {
    const double t_s = clock_->session_s(gaze.predicted);
    if (!gaze.tracked) {
      if (!lost_) {
        lost_ = true;
        lost_since_s_ = t_s;
        ++status_.connection_losses;
        batch.notices.push_back({t_s, "tracker_lost",
                                 "the headset's eye tracker lost the gaze (its pose has no valid orientation)"});
      }
      continue;
    }
    if (lost_) {
      lost_ = false;
      ++status_.reconnections;
      batch.notices.push_back({t_s, "tracker_reconnected",
                               "the headset's eye tracker has the gaze again after " + number_text(t_s - lost_since_s_) +
                                   " s"});
    }
    if (last_tracked_s_) status_.longest_gap_s = std::max(status_.longest_gap_s, t_s - *last_tracked_s_);
    last_tracked_s_ = t_s;
    // Tracker eye 0 is the right eye, the second view; eye 1 the left, the first.
    for (int eye = 0; eye < 2; ++eye) {
      const std::optional<ViewGazePoint>& point = gaze.views[eye == 0 ? 1 : 0];
      TrackerSample sample;
      sample.eye = eye;
      sample.device_time_s = static_cast<double>(gaze.runtime_time_ns) * 1e-9;
      sample.session_time_s = t_s;
      sample.pupil_diameter_mm = 0.0;  // OpenXR reports no pupil
      sample.has_pupil = false;
      if (point) {
        sample.gaze_x = point->x;
        sample.gaze_y = point->y;
      }
      sample.confidence = 1.0;  // the runtime located it; OpenXR gives no confidence beyond that
      sample.valid = true;
      batch.samples.push_back(sample);
      ++status_.samples;
    }
  }
  return batch;
}

std::string HeadsetGazeTracker::description() const { return "headset eye gaze " + display_.eye_gaze_description(); }

}  // namespace glarelab
