#pragma once
// Client of the Pupil Core network API (Pupil Capture / Pupil Service):
//  - Pupil Remote, a ZeroMQ REQ/REP endpoint (default port 50020): "SUB_PORT" answers the port of
//    the IPC backbone's PUB socket; "t" answers the current Pupil time as a decimal string. "T"
//    (set Pupil time) is never sent: it makes Pupil timestamps jump for every other client.
//  - The PUB socket sends multipart messages [topic, msgpack map]; we subscribe to
//    "pupil.0.3d", "pupil.1.3d" (diameter_3d in mm, confidence, timestamp in Pupil time, id = eye),
//    "gaze.3d." (norm_pos, origin bottom-left of the world image) and "blinks" (type onset/offset).
// Messages are received on a thread of their own. Pupil time is mapped onto the session clock by an
// offset from repeated "t" round trips (clock_offset.h), re-estimated every offset_interval_s.
// When nothing arrives for loss_timeout_s the connection is declared lost: a notice is queued and
// the client reconnects with exponential backoff; samples keep flowing once Capture answers again.
// Malformed messages are counted and skipped.
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "runner/tracker/clock_offset.h"
#include "runner/tracker/tracker_source.h"

namespace zmq {
class socket_t;
}

namespace glarelab {

struct PupilLabsSettings {
  std::string host = "127.0.0.1";
  int port = 50020;
  double request_timeout_s = 0.5;    // for one Pupil Remote request
  int offset_round_trips = 12;       // "t" requests per offset estimate
  double offset_interval_s = 2.0;    // re-estimation period during the session
  double loss_timeout_s = 1.0;       // silence after which the connection counts as lost
  double backoff_initial_s = 0.1;    // first reconnection delay, doubled up to backoff_max_s
  double backoff_max_s = 2.0;
  double gaze_max_age_s = 0.1;       // gaze older than this is not attached to a pupil sample
};

// Parses "pupil-labs://HOST:PORT" (PORT optional, default 50020). Throws TrackerError.
PupilLabsSettings parse_pupil_labs_address(const std::string& spec);

// One decoded message of the subscribed topics (times in Pupil time).
struct PupilLabsMessage {
  enum class Kind { pupil, gaze, blink } kind = Kind::pupil;
  int eye = 0;
  double timestamp_s = 0.0;
  double diameter_3d_mm = 0.0;
  double confidence = 0.0;
  double norm_x = 0.0, norm_y = 0.0;  // gaze norm_pos
  bool blink_onset = false;
};
// Decodes [topic, msgpack payload]; nullopt when malformed (wrong layout, missing or mistyped field).
std::optional<PupilLabsMessage> decode_pupil_labs_message(const std::string& topic, const void* payload,
                                                          std::size_t payload_bytes);

// Asks Pupil Remote at host:port for SUB_PORT with a short timeout: the port, or nullopt when no
// Pupil Remote answers (used by `glarelab devices` and at session start).
std::optional<int> probe_pupil_remote(const std::string& host, int port, double timeout_s);

class PupilLabsClient final : public TrackerSource {
 public:
  explicit PupilLabsClient(PupilLabsSettings settings);
  ~PupilLabsClient() override;
  // Connects, estimates the clock offset and starts the receiver. Throws TrackerError when no
  // Pupil Remote answers at the address.
  void start(const SessionClock& clock) override;
  void stop() override;
  TrackerBatch poll(double now_s) override;
  bool live() const override { return true; }
  TrackerStatus status() const override;
  std::string description() const override;
  // The latest offset estimate (Pupil time - session time).
  ClockOffsetEstimate clock_offset() const;

 private:
  struct Connection;
  void receive_loop();
  void clock_loop();
  bool connect(std::string* why);
  // One estimate from offset_round_trips "t" requests on `remote`. Replies that are not a finite
  // time are skipped, counted and noted in `batch`; nothing (and why) when Remote stops answering or
  // fewer than half the replies were times.
  std::optional<ClockOffsetEstimate> measure_offset(zmq::socket_t& remote, TrackerBatch& batch, std::string* why);
  void handle(const std::string& topic, const void* payload, std::size_t bytes, TrackerBatch& batch);

  PupilLabsSettings settings_;
  const SessionClock* clock_ = nullptr;
  std::unique_ptr<Connection> connection_;  // sockets; used only by the receiver thread once started
  TrackerQueue queue_;
  std::thread thread_;        // receives the data stream (and reconnects)
  std::thread clock_thread_;  // re-estimates the clock offset
  std::atomic<bool> stopping_{false};
  std::atomic<bool> connected_{false};
  mutable std::mutex status_mutex_;
  TrackerStatus status_;
  ClockOffsetEstimate offset_;
  std::optional<PupilLabsMessage> latest_gaze_;
};

}  // namespace glarelab
