#pragma once
// A USB port with a fake button box in it, for session tests (no virtual HID exists on the test
// machines): the session opens it through the injected HidOpener; the test presses buttons,
// unplugs it (the open device reports the unplug, new opens are refused) and plugs it back.
#include <cstdint>
#include <memory>
#include <mutex>

#include "runner/devices/hid_device.h"

namespace glarelab::test {

class FakeHidPort {
 public:
  // Reports are [report id 1, button bits]: bit b of byte 1 is button b.
  HidOpener opener() {
    return [this](const HidSelector&) -> std::unique_ptr<HidReportSource> {
      const std::lock_guard lock(mutex_);
      ++opens_;
      if (!plugged_) throw DeviceError("HID: no device (fake port empty)");
      current_ = std::make_shared<FakeHidReportSource>();
      return std::make_unique<Shared>(current_);
    };
  }
  // A press and release of button `bit`.
  void click(int bit) {
    const std::lock_guard lock(mutex_);
    if (!current_) return;
    current_->push({0x01, static_cast<std::uint8_t>(1u << bit)});
    current_->push({0x01, 0x00});
  }
  void unplug() {
    const std::lock_guard lock(mutex_);
    plugged_ = false;
    if (current_) current_->unplug();
    current_.reset();
  }
  void replug() {
    const std::lock_guard lock(mutex_);
    plugged_ = true;
  }
  int opens() {
    const std::lock_guard lock(mutex_);
    return opens_;
  }

 private:
  // What the session owns: the port keeps its own reference to push reports and to unplug.
  class Shared final : public HidReportSource {
   public:
    explicit Shared(std::shared_ptr<FakeHidReportSource> source) : source_(std::move(source)) {}
    std::optional<std::vector<std::uint8_t>> read_report(int timeout_ms) override { return source_->read_report(timeout_ms); }
    std::string description() const override { return "fake button box"; }

   private:
    std::shared_ptr<FakeHidReportSource> source_;
  };

  std::mutex mutex_;
  std::shared_ptr<FakeHidReportSource> current_;
  bool plugged_ = true;
  int opens_ = 0;
};

}  // namespace glarelab::test
