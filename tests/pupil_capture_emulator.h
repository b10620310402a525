#pragma once
// An emulator of Pupil Capture's network API, for tests: Pupil Remote (ZeroMQ REP) answering
// "SUB_PORT" with the PUB port and "t" with the current Pupil time, and a PUB socket sending
// two-frame [topic, msgpack map] messages like Capture's IPC backbone: pupil.0.3d and pupil.1.3d
// at rate_hz per eye, gaze.3d.01. and blinks onset/offset. Pupil time is steady_clock seconds plus
// a fixed offset. Diameters follow a script; during scripted blinks the pupil is reported with
// confidence 0 and diameter 0, as Capture does. Every published pupil datum is recorded (truth).
// Both sockets bind 127.0.0.1 on ports chosen by the OS.
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace glarelab::test {

struct EmulatedPupilDatum {
  int eye = 0;
  double pupil_time_s = 0.0;
  double diameter_mm = 0.0;
  double confidence = 0.0;
};

class PupilCaptureEmulator {
 public:
  // pupil_time = steady seconds + pupil_time_offset_s.
  explicit PupilCaptureEmulator(double rate_hz = 120.0, double pupil_time_offset_s = 5000.0);
  ~PupilCaptureEmulator();

  int remote_port() const { return remote_port_; }
  int pub_port() const { return pub_port_; }
  double pupil_time_offset_s() const { return pupil_time_offset_s_; }
  static double steady_now_s();

  // Starts publishing; data published after this call is recorded. Blinks: [start, end) in seconds
  // since start_publishing, for both eyes. Diameter script: mm as a function of those seconds.
  void start_publishing(std::function<double(double)> diameter_mm, std::vector<std::pair<double, double>> blinks);
  void stop_publishing();
  // While silent, neither socket answers or publishes (a tracker that went away).
  void set_silent(bool silent) { silent_ = silent; }
  // Pupil Remote's next answers to "t", in order, each after its delay (a misbehaving tracker: "nan",
  // "inf", a slow reply); once they are used up, "t" answers the time again after `t_delay_s`.
  struct TimeReply {
    std::string text;  // empty: the time, as usual
    double delay_s = 0.0;
  };
  void script_time_replies(std::vector<TimeReply> replies, double t_delay_s = 0.0);
  int time_requests() const { return time_requests_; }
  // Publishes one blink onset or offset at the current Pupil time (an onset whose offset is lost).
  void publish_blink(bool onset);
  // Sends one raw two-frame message (for malformed-input tests).
  void publish_raw(const std::string& topic, const std::string& payload);

  std::vector<EmulatedPupilDatum> published() const;
  int time_set_requests() const { return time_set_requests_; }  // "T ..." received (must stay 0)

 private:
  struct Sockets;
  void remote_loop();
  void publish_loop();

  double rate_hz_;
  double pupil_time_offset_s_;
  std::unique_ptr<Sockets> sockets_;
  int remote_port_ = 0;
  int pub_port_ = 0;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> publishing_{false};
  std::atomic<bool> silent_{false};
  std::atomic<int> time_set_requests_{0};
  std::atomic<int> time_requests_{0};
  std::vector<TimeReply> time_replies_;  // guarded by mutex_
  double t_delay_s_ = 0.0;               // guarded by mutex_
  std::thread remote_thread_;
  std::thread publish_thread_;
  mutable std::mutex mutex_;  // guards published_ and the pub socket
  std::vector<EmulatedPupilDatum> published_;
  std::function<double(double)> diameter_mm_;
  std::vector<std::pair<double, double>> blinks_;
};

}  // namespace glarelab::test
