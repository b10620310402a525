#pragma once
// A client of Monado's remote driver (tests/openxr_runtime.h, monado_remote_environment): its
// struct r_remote_data, field for field, and the TCP connection to the hub that a session's
// runtime opens. The struct is as scripts/monado/remote_eye_gaze.patch makes it: the stock
// "mndrmt3" layout and then the eye gaze the patch's eye tracker reports.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <arpa/inet.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>

#include "cli_process.h"
#include "openxr_runtime.h"

namespace glarelab::test {

struct RemotePose {
  float orientation_xyzw[4];
  float position_m[3];
};
struct RemoteView {
  float fov_rad[4];  // left, right, up, down
  RemotePose pose;
  std::uint32_t pad;
};
struct RemoteHead {
  RemoteView views[2];
  RemotePose center;
  bool per_view_data_valid, pad0, pad1, pad2;
};
struct RemoteController {
  RemotePose pose;
  float linear_velocity[3], angular_velocity[3], hand_curl[5];
  float trigger_value, squeeze_value, squeeze_force, thumbstick[2], trackpad_force, trackpad[2];
  bool hand_tracking_active, active, system_click, system_touch, a_click, a_touch, b_click, b_touch, trigger_click,
      trigger_touch, thumbstick_click, thumbstick_touch, trackpad_touch, pad0, pad1, pad2;
};
// The patch's struct r_remote_eye_gaze_data: the gaze relative to the head (-z of the orientation
// is the gaze direction) and whether it is tracked.
struct RemoteEyeGaze {
  RemotePose pose;
  bool valid, pad0, pad1, pad2;
};
struct RemoteData {
  std::uint64_t header;
  RemoteHead head;
  RemoteController left, right;
  RemoteEyeGaze eyes;
};
static_assert(sizeof(RemotePose) == 28 && sizeof(RemoteHead) == 128 && sizeof(RemoteController) == 120 &&
              sizeof(RemoteEyeGaze) == 32);
static_assert(sizeof(RemoteData) == 408, "r_remote_data with the patch's eye gaze is 408 bytes");

// The hub's start state (r_hub.c, r_create_devices): the head 1.6 m up, both controllers active,
// the gaze straight ahead and tracked.
inline RemoteData resting_state() {
  RemoteData data{};
  std::memcpy(&data.header, "mndrmt3\0", 8);
  data.head.center.orientation_xyzw[3] = 1.0f;
  data.head.center.position_m[1] = 1.6f;
  for (RemoteController* hand : {&data.left, &data.right}) {
    hand->active = true;
    hand->pose.orientation_xyzw[3] = 1.0f;
    hand->pose.position_m[0] = hand == &data.left ? -0.2f : 0.2f;
    hand->pose.position_m[1] = 1.3f;
    hand->pose.position_m[2] = -0.5f;
  }
  data.eyes.pose.orientation_xyzw[3] = 1.0f;
  data.eyes.valid = true;
  return data;
}

// A TCP port nobody listens on now (the kernel's choice for port 0), for a test's hub.
inline int free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  int port = 0;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0)
    port = ntohs(address.sin_port);
  ::close(fd);
  return port;
}

// The connection to the hub, once the runtime in the session's process listens.
inline int connect_to_hub(int port, const std::atomic<bool>& session_done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(90);
  while (!session_done && std::chrono::steady_clock::now() < deadline) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0) return fd;
    ::close(fd);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return -1;
}

inline bool send_state(int fd, const RemoteData& data) {
  const char* bytes = reinterpret_cast<const char*>(&data);
  for (std::size_t sent = 0; sent < sizeof data;) {
    const ssize_t n = ::send(fd, bytes + sent, sizeof data - sent, MSG_NOSIGNAL);
    if (n <= 0) return false;
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

// A session of `glarelab ARGUMENTS` (a run with --display openxr) under Xvfb with Monado's remote
// driver listening on `port` (with the patch's eye tracker when `eye_gaze`), ended after
// `timeout_s` at most, its validation layer writing to `validation` and its output to
// dir/output.txt. `drive` gets the connection to the hub once the runtime listens (not called when
// it never does) and the session's end, and sends the hub its states until then.
struct RemoteSessionRun {
  int status = -1;         // std::system's
  bool connected = false;  // the hub was reached
  std::string output;
};
inline RemoteSessionRun run_with_remote_hub(const std::filesystem::path& dir, int port, bool eye_gaze, int timeout_s,
                                            const std::string& arguments, const std::filesystem::path& validation,
                                            const std::function<void(int fd, const std::atomic<bool>& done)>& drive) {
  const std::filesystem::path output = dir / "output.txt";
  const std::string command = "timeout " + std::to_string(timeout_s) +
                              " xvfb-run -a -s '-screen 0 1280x1024x24 -noreset' env " +
                              monado_remote_environment(dir / "config", port, eye_gaze) +
                              " XR_CORE_VALIDATION_EXPORT_TYPE=text XR_CORE_VALIDATION_FILE_NAME='" +
                              validation.string() + "' '" + std::string(GLARELAB_BINARY) + "' " + arguments + " > '" +
                              output.string() + "' 2>&1";
  RemoteSessionRun run;
  std::atomic<bool> done{false};
  std::thread session([&] {
    run.status = std::system(command.c_str());
    done = true;
  });
  const int fd = connect_to_hub(port, done);
  run.connected = fd >= 0;
  if (run.connected) {
    drive(fd, done);
    ::close(fd);
  }
  session.join();
  run.output = read_bytes(output.string());
  return run;
}

// What every such session must show: the hub reached, a clean exit, nothing from the validation
// layer. Fatal failures here end the caller too under ASSERT_NO_FATAL_FAILURE.
inline void expect_clean_remote_session(const RemoteSessionRun& run, int port, const std::filesystem::path& validation) {
  ASSERT_TRUE(run.connected) << "the remote hub never listened on port " << port << ": " << run.output;
  ASSERT_TRUE(WIFEXITED(run.status) && WEXITSTATUS(run.status) == 0) << run.output;
  EXPECT_EQ(std::filesystem::exists(validation) ? read_bytes(validation.string()) : std::string(), "");
  EXPECT_EQ(run.output.find("VUID"), std::string::npos) << run.output;
}

}  // namespace glarelab::test
