#pragma once
// What the session loop sees of the tracker: started before the trials, polled once per frame,
// finished after them. Samples go to the TrackerLogger (its own thread and connection) and to the
// PupilFilter, whose model pupil is what the glare model gets (model_pupil_mm).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "runner/tracker/gaze_prediction.h"
#include "runner/tracker/pupil_calibration.h"
#include "runner/tracker/pupil_filter.h"
#include "runner/tracker/tracker_logger.h"
#include "runner/tracker/tracker_source.h"

namespace glarelab {

class SessionClock;

struct TrackerGaze {
  double session_time_s = 0.0;
  double x = 0.0, y = 0.0;  // normalised display coordinates, origin top left
};

struct TrackerBlinkInterval {
  double onset_s = 0.0;
  double offset_s = 0.0;  // +infinity while the blink lasts
};

struct TrackerOptions {
  std::string spec = "none";           // --tracker
  bool optional = false;               // --tracker-optional: continue without a tracker that is absent
  std::string pupil_model = "measured";  // measured | calibrated (Luidolt 2020 5.2.1 ii)
  double calibration_screen_s = 5.0;   // each of the black and white screens
};

class TrackerSession {
 public:
  // Builds the source; throws TrackerError for a bad --tracker value or an unreadable replay file.
  TrackerSession(const TrackerOptions& options, std::uint64_t seed);
  ~TrackerSession();

  // The display's own tracker (a headset's eye gaze, runner/tracker/headset_gaze_tracker.h) when
  // --tracker chose none: it is the session's tracker from here on, started, logged and read as any.
  // Ignored when a --tracker source exists (that one is the session's).
  void adopt_display_tracker(std::unique_ptr<TrackerSource> source);

  bool active() const { return source_ != nullptr; }
  bool live() const { return source_ && source_->live(); }
  bool wants_calibration() const { return active() && options_.pupil_model == "calibrated"; }
  double calibration_screen_s() const { return options_.calibration_screen_s; }

  // Starts the source. An absent tracker throws TrackerError, unless the options allow going on
  // without: then the source is dropped and the reason returned (to be logged).
  std::optional<std::string> start(const SessionClock& clock);
  // Once the session row exists: samples are logged from here on.
  void attach_log(const std::string& db_path, std::int64_t session_id);
  // Once per frame: poll, filter, hand to the logger. Never blocks on the database.
  void on_frame(double now_s);
  // Whether on_frame has run: before the session's first flip it has not, and what the tracker
  // sent since start() is not read yet.
  bool polled() const { return polled_; }
  // Calibration phases: samples filtered while a phase is open are kept for calibrate().
  void begin_calibration_phase(bool black_screen);
  // Ends calibration; returns the log line (the range, or why it failed and that the measured pupil is used).
  std::string finish_calibration(double now_s);

  // The pupil for the glare model (mm): measured, or mapped onto 2-8 mm after a calibration.
  double model_pupil_mm() const;
  // The same, or nothing before the filter accepted any sample (or without a tracker).
  std::optional<double> measured_pupil_mm() const;
  // The latest gaze that passed the filter's confidence test (valid, confidence >= its
  // min_confidence, a gaze point), in normalised display coordinates; nothing before the first.
  // Not latency-compensated: the sample as it arrived.
  std::optional<TrackerGaze> latest_gaze() const { return latest_gaze_; }
  // The gaze extrapolated to `at_s` from the recent confident samples (runner/tracker/
  // gaze_prediction.h: latency compensation); nothing before the first gaze.
  std::optional<TrackerGaze> predicted_gaze(double at_s) const {
    const std::optional<GazeSample> predicted = gaze_track_.predicted(at_s);
    if (!predicted) return std::nullopt;
    return TrackerGaze{predicted->session_time_s, predicted->x, predicted->y};
  }
  // Blinks detected so far: a blink starts at the first sample where every eye seen so far is in a
  // blink (the filter's blink flag: tracker blink topic or a confidence drop) and ends at the first
  // sample of an eye out of it. The last one is open (offset +infinity) while it lasts.
  const std::vector<TrackerBlinkInterval>& detected_blinks() const { return blinks_; }

  // One eye of a binocular tracker (eye 0 right, 1 left; a stereo session's per-eye inputs): its
  // filtered pupil (calibrated like model_pupil_mm), nothing before its first accepted sample; its
  // latest confident gaze and the gaze extrapolated from its own samples; its blinks, from its
  // first sample in a blink to its first sample out of it (the last open while it lasts).
  std::optional<double> measured_eye_pupil_mm(int eye) const;
  std::optional<TrackerGaze> latest_eye_gaze(int eye) const { return eye_gaze_[eye_index(eye)]; }
  std::optional<TrackerGaze> predicted_eye_gaze(int eye, double at_s) const {
    const std::optional<GazeSample> predicted = eye_gaze_track_[eye_index(eye)].predicted(at_s);
    if (!predicted) return std::nullopt;
    return TrackerGaze{predicted->session_time_s, predicted->x, predicted->y};
  }
  const std::vector<TrackerBlinkInterval>& detected_eye_blinks(int eye) const { return eye_blinks_[eye_index(eye)]; }
  // Stops the source, writes what is left, returns a one-line summary (empty without a tracker).
  std::string finish(double now_s);
  // Stops the source only (idempotent): before the display a display's tracker reads from closes.
  void stop_source() {
    if (source_) source_->stop();
  }

 private:
  TrackerOptions options_;
  std::unique_ptr<TrackerSource> source_;
  std::unique_ptr<TrackerLogger> logger_;
  PupilFilter filter_;
  std::int64_t samples_ = 0;
  enum class Phase { none, black, white } phase_ = Phase::none;
  std::vector<FilteredPupil> black_phase_, white_phase_;
  std::optional<PupilRange> range_;
  bool finished_ = false;
  bool polled_ = false;
  void track_gaze_and_blinks(const TrackerBatch& batch, const std::vector<FilteredPupil>& filtered);
  std::optional<TrackerGaze> latest_gaze_;
  GazeTrack gaze_track_;
  std::vector<TrackerBlinkInterval> blinks_;
  bool eye_seen_[2] = {false, false};
  bool eye_in_blink_[2] = {false, false};
  static std::size_t eye_index(int eye) { return eye == 1 ? 1 : 0; }
  std::optional<TrackerGaze> eye_gaze_[2];
  GazeTrack eye_gaze_track_[2];
  std::vector<TrackerBlinkInterval> eye_blinks_[2];
};

// Stops a session's tracker source when it goes out of scope: declared after the display, it
// stops a tracker that reads from the display (a headset's eye gaze) before the display closes,
// however the session ends.
class TrackerSourceStopper {
 public:
  explicit TrackerSourceStopper(TrackerSession& tracker) : tracker_(tracker) {}
  ~TrackerSourceStopper() { tracker_.stop_source(); }
  TrackerSourceStopper(const TrackerSourceStopper&) = delete;
  TrackerSourceStopper& operator=(const TrackerSourceStopper&) = delete;

 private:
  TrackerSession& tracker_;
};

}  // namespace glarelab
