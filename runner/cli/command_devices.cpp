// `glarelab devices`: HID devices (hidapi), USB devices (libusb) and whether a Pupil Remote answers.
// Every section is printed, "(none)" when empty, so the output always has the same shape.
#include <cstdio>
#include <iostream>
#include <memory>

#include "runner/cli/commands.h"
#include "runner/devices/device_list.h"
#include "runner/devices/hid_device.h"
#include "runner/tracker/pupil_labs_client.h"

namespace glarelab::cli {

namespace {
std::string hex4(unsigned value) {
  char text[8];
  std::snprintf(text, sizeof text, "%04x", value & 0xffffu);
  return text;
}
std::string or_unreadable(const std::string& text) { return text.empty() ? "(not readable)" : text; }
}  // namespace

Action add_devices_command(CLI::App& app) {
  auto address = std::make_shared<std::string>("127.0.0.1:50020");
  auto timeout_s = std::make_shared<double>(0.3);
  CLI::App* devices = app.add_subcommand("devices", "List HID and USB devices and whether a Pupil Remote answers");
  devices->add_option("--pupil-remote", *address, "Pupil Remote address HOST:PORT")->capture_default_str();
  devices->add_option("--timeout-s", *timeout_s, "How long to wait for Pupil Remote")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  return [=]() {
    return report_errors([&]() {
      std::cout << "HID devices (hidapi):\n";
      try {
        const auto hid = list_hid_devices();
        if (hid.empty()) std::cout << "  (none)\n";
        for (const HidDeviceInfo& d : hid)
          std::cout << "  " << hex4(d.vendor_id) << ":" << hex4(d.product_id) << " usage page 0x" << hex4(d.usage_page)
                    << " usage 0x" << hex4(d.usage) << " interface " << d.interface_number << "  "
                    << or_unreadable(d.manufacturer) << " / " << or_unreadable(d.product) << "  " << d.path << "\n";
      } catch (const DeviceError& error) {
        std::cout << "  (unavailable: " << error.what() << ")\n";
      }
      std::cout << "USB devices (libusb):\n";
      try {
        const auto usb = list_usb_devices();
        if (usb.empty()) std::cout << "  (none)\n";
        for (const UsbDeviceInfo& d : usb)
          std::cout << "  " << hex4(d.vendor_id) << ":" << hex4(d.product_id) << " bus " << d.bus << " address "
                    << d.address << "  " << or_unreadable(d.manufacturer) << " / " << or_unreadable(d.product) << "\n";
      } catch (const DeviceError& error) {
        std::cout << "  (unavailable: " << error.what() << ")\n";
      }
      const PupilLabsSettings settings = parse_pupil_labs_address("pupil-labs://" + *address);
      std::cout << "Pupil Remote (" << settings.host << ":" << settings.port << "):\n";
      if (const auto port = probe_pupil_remote(settings.host, settings.port, *timeout_s))
        std::cout << "  answers (SUB_PORT " << *port << ")\n";
      else
        std::cout << "  no answer within " << *timeout_s << " s\n";
      return 0;
    });
  };
}

}  // namespace glarelab::cli
