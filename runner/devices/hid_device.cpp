#include "runner/devices/hid_device.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/clock.h"

namespace glarelab {

namespace {

// 1-4 hex digits, optionally after 0x; nullopt otherwise.
std::optional<std::uint16_t> parse_hex16(std::string text) {
  if (text.starts_with("0x") || text.starts_with("0X")) text = text.substr(2);
  if (text.empty() || text.size() > 4) return std::nullopt;
  char* end = nullptr;
  const unsigned long value = std::strtoul(text.c_str(), &end, 16);
  if (*end != '\0' || text.find_first_of("+- ") != std::string::npos) return std::nullopt;
  return static_cast<std::uint16_t>(value);
}

std::string hex4(std::uint16_t value) {
  char text[8];
  std::snprintf(text, sizeof text, "%04x", value);
  return text;
}

}  // namespace

HidSelector parse_hid_selector(const std::string& text) {
  std::vector<std::string> parts;
  std::istringstream fields(text);
  std::string field;
  while (std::getline(fields, field, ':')) parts.push_back(field);
  if (!text.empty() && text.back() == ':') parts.push_back("");
  const auto bad = [&](const std::string& why) {
    return DeviceError("HID device '" + text + "': " + why + " (expected VID:PID or VID:PID:USAGE_PAGE in hex, e.g. 1209:0001)");
  };
  if (parts.size() < 2 || parts.size() > 3) throw bad("wrong number of fields");
  HidSelector selector;
  const auto vendor = parse_hex16(parts[0]);
  const auto product = parse_hex16(parts[1]);
  if (!vendor) throw bad("vendor id '" + parts[0] + "' is not 1-4 hex digits");
  if (!product) throw bad("product id '" + parts[1] + "' is not 1-4 hex digits");
  selector.vendor_id = *vendor;
  selector.product_id = *product;
  if (parts.size() == 3) {
    const auto page = parse_hex16(parts[2]);
    if (!page) throw bad("usage page '" + parts[2] + "' is not 1-4 hex digits");
    selector.usage_page = *page;
  }
  return selector;
}

std::string describe_hid_selector(const HidSelector& selector) {
  return hex4(selector.vendor_id) + ":" + hex4(selector.product_id) +
         (selector.usage_page ? " usage page 0x" + hex4(*selector.usage_page) : std::string());
}

std::vector<ButtonBinding> parse_button_mapping(const std::string& text) {
  std::vector<ButtonBinding> mapping;
  std::istringstream entries(text);
  std::string entry;
  while (std::getline(entries, entry, ',')) {
    const auto colon = entry.find(':');
    const auto equals = entry.find('=');
    if (colon == std::string::npos || equals == std::string::npos || equals < colon || equals + 1 == entry.size())
      throw DeviceError("button mapping: '" + entry + "' is not BYTE:BIT=RESPONSE");
    char* end = nullptr;
    const std::string byte_text = entry.substr(0, colon);
    const std::string bit_text = entry.substr(colon + 1, equals - colon - 1);
    const long byte_index = std::strtol(byte_text.c_str(), &end, 10);
    const bool byte_ok = !byte_text.empty() && *end == '\0' && byte_index >= 0 && byte_index < 64;
    const long bit = std::strtol(bit_text.c_str(), &end, 10);
    const bool bit_ok = !bit_text.empty() && *end == '\0' && bit >= 0 && bit < 8;
    if (!byte_ok || !bit_ok)
      throw DeviceError("button mapping: '" + entry + "': byte must be 0-63 and bit 0-7");
    mapping.push_back({static_cast<std::size_t>(byte_index), static_cast<int>(bit), entry.substr(equals + 1)});
  }
  if (mapping.empty()) throw DeviceError("button mapping: empty");
  return mapping;
}

void FakeHidReportSource::push(std::vector<std::uint8_t> report) {
  {
    const std::lock_guard lock(mutex_);
    reports_.push_back(std::move(report));
  }
  ready_.notify_all();
}

void FakeHidReportSource::unplug() {
  {
    const std::lock_guard lock(mutex_);
    unplugged_ = true;
  }
  ready_.notify_all();
}

std::optional<std::vector<std::uint8_t>> FakeHidReportSource::read_report(int timeout_ms) {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [this] { return unplugged_ || !reports_.empty(); });
  if (!reports_.empty()) {
    auto report = std::move(reports_.front());
    reports_.pop_front();
    return report;
  }
  if (unplugged_) return std::nullopt;
  return std::vector<std::uint8_t>{};
}

HidResponseDevice::HidResponseDevice(std::unique_ptr<HidReportSource> source, std::vector<ButtonBinding> mapping,
                                     const SessionClock& clock)
    : source_(std::move(source)), mapping_(std::move(mapping)), clock_(clock), pressed_(mapping_.size(), false) {}

HidResponseDevice::~HidResponseDevice() { stop(); }

void HidResponseDevice::start() {
  stopping_ = false;
  thread_ = std::thread([this] { read_loop(); });
}

void HidResponseDevice::stop() {
  stopping_ = true;
  if (thread_.joinable()) thread_.join();
}

std::vector<ButtonEvent> HidResponseDevice::take_events() {
  const std::lock_guard lock(events_mutex_);
  std::vector<ButtonEvent> out;
  std::swap(out, events_);
  return out;
}

void HidResponseDevice::read_loop() {
  while (!stopping_) {
    const auto report = source_->read_report(20);
    // Stamped before anything else is done with the report: this is the response time.
    const double read_s = clock_.now_s();
    if (!report) {
      unplugged_ = true;
      return;
    }
    if (report->empty()) continue;
    ++reports_read_;
    std::vector<ButtonEvent> changes;
    for (std::size_t i = 0; i < mapping_.size(); ++i) {
      const ButtonBinding& binding = mapping_[i];
      const bool down = binding.byte_index < report->size() && (((*report)[binding.byte_index] >> binding.bit) & 1) != 0;
      if (down != pressed_[i]) changes.push_back({binding.response, down, read_s});
      pressed_[i] = down;
    }
    if (changes.empty()) continue;
    const std::lock_guard lock(events_mutex_);
    events_.insert(events_.end(), changes.begin(), changes.end());
  }
}

}  // namespace glarelab
