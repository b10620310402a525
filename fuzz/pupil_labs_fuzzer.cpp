// Fuzz target: decoding of Pupil Capture's messages (runner/tracker/pupil_labs_client.h), which
// arrive over the network from another program. Input: the topic, a NUL byte, then the msgpack
// payload. decode_pupil_labs_message must never throw: a malformed message is nullopt (counted and
// skipped by the client). A decoded message must hold what the client relies on: an eye of 0 or 1
// for pupil samples, a finite timestamp (it is mapped onto the session clock), a confidence in
// [0, 1] and a non-negative diameter.
#include <cstddef>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "runner/tracker/pupil_labs_client.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glarelab;
  const void* nul = std::memchr(data, 0, size);
  const std::size_t topic_size = nul == nullptr ? size : static_cast<std::size_t>(static_cast<const std::uint8_t*>(nul) - data);
  const std::string topic(reinterpret_cast<const char*>(data), topic_size);
  const std::uint8_t* payload = data + topic_size + (nul == nullptr ? 0 : 1);
  const std::size_t payload_size = size - topic_size - (nul == nullptr ? 0 : 1);
  const auto message = decode_pupil_labs_message(topic, payload, payload_size);
  if (!message) return 0;
  const bool eye_ok = message->kind != PupilLabsMessage::Kind::pupil || message->eye == 0 || message->eye == 1;
  if (!eye_ok || !std::isfinite(message->timestamp_s) || !(message->confidence >= 0.0 && message->confidence <= 1.0) || !(message->diameter_3d_mm >= 0.0)) {
    std::fprintf(stderr, "decoded message out of range: eye %d timestamp %g confidence %g diameter %g\n",
                 message->eye, message->timestamp_s, message->confidence, message->diameter_3d_mm);
    std::abort();
  }
  return 0;
}
