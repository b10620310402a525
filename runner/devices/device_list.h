#pragma once
// What is connected: HID devices (hidapi) and USB devices (libusb), for `glarelab devices` and
// for opening a response device by id.
#include <cstdint>
#include <string>
#include <vector>

namespace glarelab {

struct HidDeviceInfo {
  std::uint16_t vendor_id = 0;
  std::uint16_t product_id = 0;
  std::uint16_t usage_page = 0;
  std::uint16_t usage = 0;
  int interface_number = -1;
  std::string manufacturer;
  std::string product;
  std::string path;
};

struct UsbDeviceInfo {
  std::uint16_t vendor_id = 0;
  std::uint16_t product_id = 0;
  int bus = 0;
  int address = 0;
  std::string manufacturer;  // empty when the device cannot be opened to read its strings
  std::string product;
};

// Throw DeviceError when the library cannot be initialised (no USB subsystem at all).
std::vector<HidDeviceInfo> list_hid_devices();
std::vector<UsbDeviceInfo> list_usb_devices();

}  // namespace glarelab
