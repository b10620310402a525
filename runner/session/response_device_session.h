#pragma once
// What a session sees of its response device (docs/DEVICES.md): chosen on the command line
// (--response-device VID:PID[:USAGE_PAGE] --buttons BYTE:BIT=NAME,...), opened on the session
// clock before anything is written, polled for button presses, and reopened by the same selector
// after an unplug (attempts with backoff while the session is paused).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "runner/devices/hid_device.h"

namespace glarelab {

class SessionClock;

struct ResponseDeviceOptions {
  std::string selector;   // --response-device; empty: no device
  std::string buttons;    // --buttons
  bool optional = false;  // --response-device-optional: continue without a device absent at start
  HidOpener open;         // empty: open_hidapi_device (library callers and tests inject their own)
};

class ResponseDeviceSession {
 public:
  // Checks the options; a malformed selector or mapping, or one without the other, is a
  // ConfigError naming the option (exit 2) before anything is opened.
  explicit ResponseDeviceSession(ResponseDeviceOptions options);
  ~ResponseDeviceSession();
  ResponseDeviceSession(const ResponseDeviceSession&) = delete;
  ResponseDeviceSession& operator=(const ResponseDeviceSession&) = delete;

  bool configured() const { return selector_.has_value(); }
  bool active() const { return device_ != nullptr; }
  // "HID 1209:0001 (1:0=left,1:1=right)", the device's own name once it is open.
  std::string description() const;

  // Opens the device and starts its reader thread, stamping on `clock`. An absent device throws
  // DeviceError (exit 3) unless optional: then no device is used and the reason is returned.
  std::optional<std::string> start(const SessionClock& clock);
  // The presses since the last call, in order, each stamped on the session clock when its report
  // was read (releases are dropped: only a press answers or adjusts).
  std::vector<ButtonEvent> take_presses();
  // The device stopped answering (a read error: unplugged). Presses read before are still queued.
  bool unplugged() const;

  // Reconnection while paused. begin_reconnecting at the unplug; then try_reconnect once per
  // frame: an attempt is made at once and then after 0.1 s, doubling to at most 2 s between
  // attempts (session clock). True once the same selector opened again (the reader restarted).
  void begin_reconnecting(double now_s);
  bool try_reconnect(double now_s);
  int reconnect_attempts() const { return attempts_; }
  // Counted for the summary.
  void note_pause(double paused_s);

  // Stops the reader (before the clock it stamps on goes away); safe to call twice.
  void stop();
  // One line: presses, unplugs, the longest pause (empty without a device).
  std::string summary() const;

 private:
  ResponseDeviceOptions options_;
  std::optional<HidSelector> selector_;
  std::vector<ButtonBinding> mapping_;
  const SessionClock* clock_ = nullptr;
  std::unique_ptr<HidResponseDevice> device_;
  std::string device_name_;
  std::int64_t presses_ = 0;
  int unplugs_ = 0;
  double longest_pause_s_ = 0.0;
  double next_attempt_s_ = 0.0;
  double backoff_s_ = 0.0;
  int attempts_ = 0;
};

// Stops the device's reader when it goes out of scope: declared after the session clock, so the
// reader never stamps on a clock that is gone.
class ResponseDeviceStopper {
 public:
  explicit ResponseDeviceStopper(ResponseDeviceSession& device) : device_(device) {}
  ~ResponseDeviceStopper() { device_.stop(); }
  ResponseDeviceStopper(const ResponseDeviceStopper&) = delete;
  ResponseDeviceStopper& operator=(const ResponseDeviceStopper&) = delete;

 private:
  ResponseDeviceSession& device_;
};

}  // namespace glarelab
