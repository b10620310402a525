#pragma once
// The eye-tracker seam. A TrackerSource delivers pupil and gaze samples stamped on the session
// clock; the session loop polls it once per frame, hands the samples to the TrackerLogger (which
// writes them from its own thread) and to the PupilFilter (which makes the model pupil).
//  - Live sources (Pupil Labs) receive on a thread of their own into a TrackerQueue; poll() drains it.
//  - Offline sources (simulated, replay) are pure functions of time: poll(t) returns every sample
//    with session_time_s <= t, so offscreen runs on the virtual clock stay deterministic.
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace glarelab {

class SessionClock;

// A tracker could not be used (absent at start, bad address, unreadable replay file).
class TrackerError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TrackerSample {
  int eye = 0;                     // 0 right, 1 left (Pupil Labs eye ids)
  double device_time_s = 0.0;      // the tracker's own clock (Pupil time for Pupil Labs)
  double session_time_s = 0.0;     // the same instant on the session clock
  double pupil_diameter_mm = 0.0;  // as reported; 0 during a blink, like a real tracker
  double gaze_x = -1.0;            // normalised display coordinates, 0..1 from the left
  double gaze_y = -1.0;            // 0..1 from the top; both < 0 when no gaze is known
  double confidence = 0.0;         // 0..1
  bool valid = false;              // the tracker's own judgement (confidence > 0 and a diameter)
  // false: the tracker reports gaze alone (a headset's OpenXR eye gaze): no pupil and no blink
  // signal, so the pupil filter leaves the sample out rather than reading it as a closed eye.
  bool has_pupil = true;
  bool has_gaze() const { return gaze_x >= 0.0 && gaze_y >= 0.0; }
};

// A blink reported by the tracker itself (Pupil Labs "blinks" topic), on the session clock.
struct BlinkEvent {
  double session_time_s = 0.0;
  bool onset = true;  // false: offset
  double confidence = 0.0;
};

// Something that happened to the connection (lost, reconnected, clock re-estimated), for the log.
struct TrackerNotice {
  double session_time_s = 0.0;
  std::string kind;  // tracker_lost | tracker_reconnected | tracker_clock | tracker_malformed
  std::string message;
};

struct TrackerBatch {
  std::vector<TrackerSample> samples;
  std::vector<BlinkEvent> blinks;
  std::vector<TrackerNotice> notices;
  bool empty() const { return samples.empty() && blinks.empty() && notices.empty(); }
  void append(TrackerBatch&& other);
};

// Counters for the session summary.
struct TrackerStatus {
  std::int64_t samples = 0;
  std::int64_t malformed_messages = 0;
  int connection_losses = 0;
  int reconnections = 0;
  double longest_gap_s = 0.0;  // longest time without a data message, across reconnections
  std::int64_t clock_faults = 0;  // clock replies that were not a time (Pupil Remote "t": nan, inf, text)
};

// Multi-producer, single-consumer queue of batches. push() never blocks for long (a mutex held
// for a vector append), so a receiver thread or the frame loop can always hand data over.
class TrackerQueue {
 public:
  void push(TrackerBatch&& batch);
  // Everything queued so far (empty when nothing is).
  TrackerBatch take_all();
  // Waits up to timeout_s for data or close(); returns what is there.
  TrackerBatch wait_and_take(double timeout_s);
  void close();
  bool closed() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  TrackerBatch pending_;
  bool closed_ = false;
};

class TrackerSource {
 public:
  virtual ~TrackerSource() = default;
  // Begins delivering samples stamped on `clock` (which must outlive the source). Throws
  // TrackerError when the tracker cannot be reached.
  virtual void start(const SessionClock& clock) = 0;
  // Stops delivery (joins any thread). Idempotent.
  virtual void stop() = 0;
  // Samples up to session time `now_s` (offline sources) or everything received (live ones).
  virtual TrackerBatch poll(double now_s) = 0;
  // True when samples arrive in real time: the session must then run on a real-time clock.
  virtual bool live() const = 0;
  virtual TrackerStatus status() const = 0;
  virtual std::string description() const = 0;
};

// Builds a source from a --tracker value: none | simulated | replay:FILE[.csv] |
// replay:FILE.db#SESSION | pupil-labs://HOST:PORT. Returns null for "none". `seed` drives the
// simulated tracker. Throws TrackerError for an unknown or malformed value.
std::unique_ptr<TrackerSource> make_tracker_source(const std::string& spec, std::uint64_t seed);

}  // namespace glarelab
