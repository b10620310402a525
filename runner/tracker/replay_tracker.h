#pragma once
// Replays recorded tracker data on the session clock: samples (and blinks) with session_time_s <= t
// are returned by poll(t), in their recorded order, with their recorded values.
//  - replay:FILE.csv: header row with the columns eye, device_time_s, session_time_s,
//    pupil_diameter_mm, gaze_x, gaze_y, confidence, valid (empty cells: no diameter / no gaze);
//    an optional column `blink` (onset | offset) turns a row into a blink event (other cells ignored
//    except session_time_s and confidence).
//  - replay:FILE.db#SESSION: tracker_samples of that session in insertion order, and its
//    blink_onset / blink_offset events from session_events.
#include <cstddef>
#include <string>
#include <vector>

#include "runner/tracker/tracker_source.h"

namespace glarelab {

struct RecordedTrack {
  std::vector<TrackerSample> samples;
  std::vector<BlinkEvent> blinks;  // sorted by time
};

// Throws TrackerError naming the file (and line for CSV) on unreadable input.
RecordedTrack read_tracker_csv(const std::string& path);
RecordedTrack read_tracker_database(const std::string& path, std::int64_t session_id);

class ReplayTracker final : public TrackerSource {
 public:
  ReplayTracker(RecordedTrack track, std::string origin);
  void start(const SessionClock&) override {}
  void stop() override {}
  TrackerBatch poll(double now_s) override;
  bool live() const override { return false; }
  TrackerStatus status() const override { return status_; }
  std::string description() const override { return "replay of " + origin_; }

 private:
  RecordedTrack track_;
  std::string origin_;
  std::size_t next_sample_ = 0;
  std::size_t next_blink_ = 0;
  TrackerStatus status_;
};

}  // namespace glarelab
