#include "runner/session/response_device_session.h"

#include <algorithm>
#include <cstdio>

#include "core/errors.h"
#include "core/clock.h"

namespace glarelab {
namespace {

constexpr double kFirstBackoffS = 0.1;
constexpr double kLongestBackoffS = 2.0;

std::string mapping_text(const std::vector<ButtonBinding>& mapping) {
  std::string text;
  for (const ButtonBinding& binding : mapping) {
    if (!text.empty()) text += ",";
    text += std::to_string(binding.byte_index) + ":" + std::to_string(binding.bit) + "=" + binding.response;
  }
  return text;
}

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", seconds);
  return text;
}

}  // namespace

ResponseDeviceSession::ResponseDeviceSession(ResponseDeviceOptions options) : options_(std::move(options)) {
  if (options_.selector.empty()) {
    if (!options_.buttons.empty())
      throw ConfigError({"--buttons", 0, 0}, "buttons", "a button mapping needs --response-device VID:PID");
    if (options_.optional)
      throw ConfigError({"--response-device-optional", 0, 0}, "response-device-optional",
                        "needs --response-device VID:PID");
    return;
  }
  try {
    selector_ = parse_hid_selector(options_.selector);
  } catch (const DeviceError& error) {
    throw ConfigError({"--response-device", 0, 0}, "response-device", error.what());
  }
  if (options_.buttons.empty())
    throw ConfigError({"--buttons", 0, 0}, "buttons",
                      "--response-device needs --buttons BYTE:BIT=NAME,... (docs/DEVICES.md)");
  try {
    mapping_ = parse_button_mapping(options_.buttons);
  } catch (const DeviceError& error) {
    throw ConfigError({"--buttons", 0, 0}, "buttons", error.what());
  }
  if (!options_.open) options_.open = open_hidapi_device;
}

ResponseDeviceSession::~ResponseDeviceSession() { stop(); }

std::string ResponseDeviceSession::description() const {
  if (!selector_) return "";
  return (device_name_.empty() ? "HID " + describe_hid_selector(*selector_) : device_name_) + " (" +
         mapping_text(mapping_) + ")";
}

std::optional<std::string> ResponseDeviceSession::start(const SessionClock& clock) {
  if (!selector_) return std::nullopt;
  clock_ = &clock;
  std::unique_ptr<HidReportSource> source;
  try {
    source = options_.open(*selector_);
  } catch (const DeviceError& error) {
    if (!options_.optional) throw;
    return std::string(error.what()) + "; continuing without a response device (--response-device-optional)";
  }
  device_name_ = source->description();
  device_ = std::make_unique<HidResponseDevice>(std::move(source), mapping_, clock);
  device_->start();
  return std::nullopt;
}

std::vector<ButtonEvent> ResponseDeviceSession::take_presses() {
  std::vector<ButtonEvent> presses;
  if (!device_) return presses;
  for (ButtonEvent& event : device_->take_events())
    if (event.pressed) presses.push_back(std::move(event));
  presses_ += static_cast<std::int64_t>(presses.size());
  return presses;
}

bool ResponseDeviceSession::unplugged() const { return device_ && device_->unplugged(); }

void ResponseDeviceSession::begin_reconnecting(double now_s) {
  ++unplugs_;
  attempts_ = 0;
  next_attempt_s_ = now_s;
  backoff_s_ = kFirstBackoffS;
}

bool ResponseDeviceSession::try_reconnect(double now_s) {
  if (!device_ || !device_->unplugged()) return true;
  if (now_s < next_attempt_s_) return false;
  ++attempts_;
  next_attempt_s_ = now_s + backoff_s_;
  backoff_s_ = std::min(2.0 * backoff_s_, kLongestBackoffS);
  std::unique_ptr<HidReportSource> source;
  try {
    source = options_.open(*selector_);
  } catch (const DeviceError&) {
    return false;  // still absent: the next attempt after the backoff
  }
  device_->stop();
  device_name_ = source->description();
  device_ = std::make_unique<HidResponseDevice>(std::move(source), mapping_, *clock_);
  device_->start();
  return true;
}

void ResponseDeviceSession::note_pause(double paused_s) { longest_pause_s_ = std::max(longest_pause_s_, paused_s); }

void ResponseDeviceSession::stop() {
  if (device_) device_->stop();
}

std::string ResponseDeviceSession::summary() const {
  if (!device_) return "";
  return "response device " + description() + ": " + std::to_string(presses_) + " presses, " +
         std::to_string(unplugs_) + " unplug(s), longest pause " + seconds_text(longest_pause_s_) + " s";
}

}  // namespace glarelab
