// HidReportSource for real devices through hidapi (hidraw backend: no kernel driver detaching).
#include <hidapi/hidapi.h>

#include "runner/devices/device_list.h"
#include "runner/devices/hid_device.h"

namespace glarelab {

namespace {

class HidapiReportSource final : public HidReportSource {
 public:
  HidapiReportSource(hid_device* device, std::string description) : device_(device), description_(std::move(description)) {}
  ~HidapiReportSource() override { hid_close(device_); }
  HidapiReportSource(const HidapiReportSource&) = delete;
  HidapiReportSource& operator=(const HidapiReportSource&) = delete;

  std::optional<std::vector<std::uint8_t>> read_report(int timeout_ms) override {
    std::vector<std::uint8_t> buffer(64);
    const int bytes = hid_read_timeout(device_, buffer.data(), buffer.size(), timeout_ms);
    if (bytes < 0) return std::nullopt;  // the device went away
    buffer.resize(static_cast<std::size_t>(bytes));
    return buffer;
  }
  std::string description() const override { return description_; }

 private:
  hid_device* device_;
  std::string description_;
};

}  // namespace

std::unique_ptr<HidReportSource> open_hidapi_device(const HidSelector& selector) {
  const std::string wanted = describe_hid_selector(selector);
  if (hid_init() != 0) throw DeviceError("HID: hidapi could not be initialised");
  for (const HidDeviceInfo& info : list_hid_devices()) {
    if (info.vendor_id != selector.vendor_id || info.product_id != selector.product_id) continue;
    if (selector.usage_page && info.usage_page != *selector.usage_page) continue;
    hid_device* device = hid_open_path(info.path.c_str());
    if (device == nullptr)
      throw DeviceError("HID: " + wanted + " at " + info.path + " cannot be opened (permissions of /dev/hidraw*?)");
    return std::make_unique<HidapiReportSource>(device, "HID " + wanted + " " + info.product);
  }
  throw DeviceError("HID: no device " + wanted + " (glarelab devices lists what is connected)");
}

}  // namespace glarelab
