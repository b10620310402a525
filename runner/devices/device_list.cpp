#include "runner/devices/device_list.h"

#include <hidapi/hidapi.h>
#include <libusb.h>

#include <cwchar>

#include "runner/devices/hid_device.h"

namespace glarelab {

namespace {

std::string narrow(const wchar_t* text) {
  if (text == nullptr) return {};
  std::string out;
  for (; *text != L'\0'; ++text) out.push_back(*text < 128 ? static_cast<char>(*text) : '?');
  return out;
}

std::string usb_string(libusb_device_handle* handle, std::uint8_t index) {
  if (handle == nullptr || index == 0) return {};
  unsigned char text[256];
  const int length = libusb_get_string_descriptor_ascii(handle, index, text, sizeof text);
  return length > 0 ? std::string(reinterpret_cast<char*>(text), static_cast<std::size_t>(length)) : std::string();
}

}  // namespace

std::vector<HidDeviceInfo> list_hid_devices() {
  if (hid_init() != 0) throw DeviceError("HID: hidapi could not be initialised");
  std::vector<HidDeviceInfo> devices;
  hid_device_info* list = hid_enumerate(0, 0);
  for (const hid_device_info* info = list; info != nullptr; info = info->next) {
    HidDeviceInfo device;
    device.vendor_id = info->vendor_id;
    device.product_id = info->product_id;
    device.usage_page = info->usage_page;
    device.usage = info->usage;
    device.interface_number = info->interface_number;
    device.manufacturer = narrow(info->manufacturer_string);
    device.product = narrow(info->product_string);
    device.path = info->path != nullptr ? info->path : "";
    devices.push_back(device);
  }
  hid_free_enumeration(list);
  return devices;
}

std::vector<UsbDeviceInfo> list_usb_devices() {
  libusb_context* context = nullptr;
  const int init = libusb_init(&context);
  if (init != 0) throw DeviceError(std::string("USB: libusb could not be initialised: ") + libusb_error_name(init));
  libusb_device** list = nullptr;
  const ssize_t count = libusb_get_device_list(context, &list);
  std::vector<UsbDeviceInfo> devices;
  for (ssize_t i = 0; i < count; ++i) {
    libusb_device* device = list[i];
    libusb_device_descriptor descriptor{};
    if (libusb_get_device_descriptor(device, &descriptor) != 0) continue;
    UsbDeviceInfo info;
    info.vendor_id = descriptor.idVendor;
    info.product_id = descriptor.idProduct;
    info.bus = libusb_get_bus_number(device);
    info.address = libusb_get_device_address(device);
    libusb_device_handle* handle = nullptr;
    // Strings need the device opened; without permission they stay empty.
    if (libusb_open(device, &handle) == 0) {
      info.manufacturer = usb_string(handle, descriptor.iManufacturer);
      info.product = usb_string(handle, descriptor.iProduct);
      libusb_close(handle);
    }
    devices.push_back(info);
  }
  if (count >= 0) libusb_free_device_list(list, 1);
  libusb_exit(context);
  return devices;
}

}  // namespace glarelab
