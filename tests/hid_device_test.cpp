// Response devices through the project's HID interface, with a fake device (no virtual HID here).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "cli_process.h"
#include "pupil_capture_emulator.h"
#include "core/clock.h"
#include "runner/devices/hid_device.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

// A session clock the test sets by hand, so the stamps can be checked exactly.
class ManualClock final : public SessionClock {
 public:
  double now_s() const override { return now_s_.load(); }
  double on_flip() override { return now_s(); }
  std::string name() const override { return "manual"; }
  bool keeps_real_time() const override { return false; }
  void set(double t) { now_s_ = t; }

 private:
  std::atomic<double> now_s_{0.0};
};

std::vector<ButtonEvent> wait_for_events(HidResponseDevice& device, std::size_t count) {
  std::vector<ButtonEvent> events;
  for (int i = 0; i < 200 && events.size() < count; ++i) {
    auto more = device.take_events();
    events.insert(events.end(), more.begin(), more.end());
    if (events.size() < count) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return events;
}

TEST(HidDevice, MapsBitsToResponsesAndStampsReadsOnTheSessionClock) {
  const auto mapping = parse_button_mapping("1:0=left,1:1=right,2:7=confirm");
  ASSERT_EQ(mapping.size(), 3u);
  EXPECT_EQ(mapping[2].byte_index, 2u);
  EXPECT_EQ(mapping[2].bit, 7);
  auto fake = std::make_unique<FakeHidReportSource>();
  FakeHidReportSource* device_side = fake.get();
  ManualClock clock;
  HidResponseDevice device(std::move(fake), mapping, clock);
  device.start();

  clock.set(1.25);
  device_side->push({0x01, 0b00000001, 0x00});  // report id 1, left down
  auto events = wait_for_events(device, 1);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].response, "left");
  EXPECT_TRUE(events[0].pressed);
  EXPECT_EQ(events[0].session_time_s, 1.25);

  clock.set(2.5);
  device_side->push({0x01, 0b00000010, 0x80});  // left up, right down, confirm down
  events = wait_for_events(device, 3);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].response, "left");
  EXPECT_FALSE(events[0].pressed);
  EXPECT_EQ(events[1].response, "right");
  EXPECT_TRUE(events[1].pressed);
  EXPECT_EQ(events[2].response, "confirm");
  for (const ButtonEvent& event : events) EXPECT_EQ(event.session_time_s, 2.5);

  device_side->push({0x01, 0b00000010, 0x80});  // unchanged: no event
  device_side->unplug();
  for (int i = 0; i < 200 && !device.unplugged(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_TRUE(device.unplugged());
  EXPECT_TRUE(device.take_events().empty());
  EXPECT_EQ(device.reports_read(), 3);
}

TEST(HidDevice, RejectsBadMappings) {
  EXPECT_THROW(parse_button_mapping("1:8=left"), DeviceError);
  EXPECT_THROW(parse_button_mapping("x:0=left"), DeviceError);
  EXPECT_THROW(parse_button_mapping("1:0"), DeviceError);
  EXPECT_THROW(parse_button_mapping(""), DeviceError);
}

TEST(HidDevice, DevicesCommandListsEverySection) {
  test::ScratchDir dir;
  const auto run = test::run_glarelab({"devices", "--pupil-remote", "127.0.0.1:1", "--timeout-s", "0.2"}, dir.path());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("HID devices (hidapi):"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("USB devices (libusb):"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("Pupil Remote (127.0.0.1:1):\n  no answer"), std::string::npos) << run.output;

  test::PupilCaptureEmulator emulator;
  const std::string address = "127.0.0.1:" + std::to_string(emulator.remote_port());
  const auto found = test::run_glarelab({"devices", "--pupil-remote", address}, dir.path());
  EXPECT_EQ(found.exit_code, 0) << found.output;
  EXPECT_NE(found.output.find("answers (SUB_PORT " + std::to_string(emulator.pub_port()) + ")"), std::string::npos)
      << found.output;
}

}  // namespace
}  // namespace glarelab
