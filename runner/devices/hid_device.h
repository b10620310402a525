#pragma once
// Response devices (button boxes, gamepads) over USB HID. Two layers:
//  - HidReportSource: a raw device that yields input reports (hidapi_device.cpp for real devices,
//    FakeHidReportSource for tests: no virtual HID exists on the test machines).
//  - HidResponseDevice: reads reports on a thread of its own, stamps each on the session clock
//    right after the read returns, and turns changes of mapped bits into button events.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace glarelab {

class SessionClock;

class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Which device: vendor and product id, and optionally the HID usage page (a composite device
// exposes one interface per usage page, e.g. 0x01 generic desktop, 0x0C consumer).
struct HidSelector {
  std::uint16_t vendor_id = 0;
  std::uint16_t product_id = 0;
  std::optional<std::uint16_t> usage_page;
};

// Parses "VID:PID" or "VID:PID:USAGE_PAGE", each 1-4 hex digits with an optional 0x
// ("1209:0001", "0x046d:0xc216:0x01"). Throws DeviceError naming the text.
HidSelector parse_hid_selector(const std::string& text);
// "1209:0001" or "1209:0001 usage page 0x0001".
std::string describe_hid_selector(const HidSelector& selector);

// One mapped button: bit `bit` (0 = least significant) of byte `byte_index` of the input report
// (byte 0 is the report id for devices that number their reports) means `response`.
struct ButtonBinding {
  std::size_t byte_index = 0;
  int bit = 0;
  std::string response;  // e.g. "left", "right", "1"
};

// Parses "BYTE:BIT=RESPONSE,..." (e.g. "1:0=left,1:1=right"). Throws DeviceError naming the entry.
std::vector<ButtonBinding> parse_button_mapping(const std::string& text);

struct ButtonEvent {
  std::string response;
  bool pressed = true;           // false: released
  double session_time_s = 0.0;   // right after the report was read
};

class HidReportSource {
 public:
  virtual ~HidReportSource() = default;
  // Waits up to timeout_ms for one input report: the report, an empty vector on timeout, or
  // nullopt when the device is gone (unplugged).
  virtual std::optional<std::vector<std::uint8_t>> read_report(int timeout_ms) = 0;
  virtual std::string description() const = 0;
};

// Opens a real device through hidapi (hidraw backend). Throws DeviceError when no device matches.
std::unique_ptr<HidReportSource> open_hidapi_device(const HidSelector& selector);

// How a session opens (and after an unplug, reopens) its device: open_hidapi_device for real
// devices; tests pass a function that hands out fake devices and can refuse (unplugged).
using HidOpener = std::function<std::unique_ptr<HidReportSource>(const HidSelector&)>;

// A device for tests: reports pushed by the test are read in order.
class FakeHidReportSource final : public HidReportSource {
 public:
  void push(std::vector<std::uint8_t> report);
  void unplug();
  std::optional<std::vector<std::uint8_t>> read_report(int timeout_ms) override;
  std::string description() const override { return "fake HID device"; }

 private:
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::vector<std::uint8_t>> reports_;
  bool unplugged_ = false;
};

class HidResponseDevice {
 public:
  HidResponseDevice(std::unique_ptr<HidReportSource> source, std::vector<ButtonBinding> mapping,
                    const SessionClock& clock);
  ~HidResponseDevice();
  HidResponseDevice(const HidResponseDevice&) = delete;
  HidResponseDevice& operator=(const HidResponseDevice&) = delete;

  void start();
  void stop();
  // Events since the last call, in order.
  std::vector<ButtonEvent> take_events();
  bool unplugged() const { return unplugged_; }
  std::int64_t reports_read() const { return reports_read_; }
  std::string description() const { return source_->description(); }

 private:
  void read_loop();

  std::unique_ptr<HidReportSource> source_;
  std::vector<ButtonBinding> mapping_;
  const SessionClock& clock_;
  std::thread thread_;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> unplugged_{false};
  std::atomic<std::int64_t> reports_read_{0};
  std::mutex events_mutex_;
  std::vector<ButtonEvent> events_;
  std::vector<bool> pressed_;
};

}  // namespace glarelab
