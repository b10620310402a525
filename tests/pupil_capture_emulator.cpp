#include "pupil_capture_emulator.h"

#include <msgpack.hpp>
#include <zmq.hpp>

#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>

namespace glarelab::test {

struct PupilCaptureEmulator::Sockets {
  zmq::context_t context{1};
  zmq::socket_t remote{context, zmq::socket_type::rep};
  zmq::socket_t pub{context, zmq::socket_type::pub};
};

namespace {

int bound_port(zmq::socket_t& socket) {
  const std::string endpoint = socket.get(zmq::sockopt::last_endpoint);  // tcp://127.0.0.1:PORT
  return std::stoi(endpoint.substr(endpoint.rfind(':') + 1));
}

std::string pack_pupil(int eye, double timestamp, double diameter_mm, double confidence) {
  msgpack::sbuffer buffer;
  msgpack::packer<msgpack::sbuffer> packer(buffer);
  packer.pack_map(6);
  packer.pack(std::string("topic")), packer.pack("pupil." + std::to_string(eye) + ".3d");
  packer.pack(std::string("id")), packer.pack(eye);
  packer.pack(std::string("timestamp")), packer.pack(timestamp);
  packer.pack(std::string("confidence")), packer.pack(confidence);
  packer.pack(std::string("diameter_3d")), packer.pack(diameter_mm);
  packer.pack(std::string("norm_pos"));
  packer.pack_array(2), packer.pack(0.5), packer.pack(0.5);
  return std::string(buffer.data(), buffer.size());
}

std::string pack_gaze(double timestamp, double x, double y, double confidence) {
  msgpack::sbuffer buffer;
  msgpack::packer<msgpack::sbuffer> packer(buffer);
  packer.pack_map(4);
  packer.pack(std::string("topic")), packer.pack(std::string("gaze.3d.01."));
  packer.pack(std::string("timestamp")), packer.pack(timestamp);
  packer.pack(std::string("confidence")), packer.pack(confidence);
  packer.pack(std::string("norm_pos"));
  packer.pack_array(2), packer.pack(x), packer.pack(y);
  return std::string(buffer.data(), buffer.size());
}

std::string pack_blink(double timestamp, bool onset) {
  msgpack::sbuffer buffer;
  msgpack::packer<msgpack::sbuffer> packer(buffer);
  packer.pack_map(4);
  packer.pack(std::string("topic")), packer.pack(std::string("blink"));
  packer.pack(std::string("type")), packer.pack(std::string(onset ? "onset" : "offset"));
  packer.pack(std::string("timestamp")), packer.pack(timestamp);
  packer.pack(std::string("confidence")), packer.pack(0.9);
  return std::string(buffer.data(), buffer.size());
}

}  // namespace

double PupilCaptureEmulator::steady_now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

PupilCaptureEmulator::PupilCaptureEmulator(double rate_hz, double pupil_time_offset_s)
    : rate_hz_(rate_hz), pupil_time_offset_s_(pupil_time_offset_s), sockets_(std::make_unique<Sockets>()) {
  sockets_->remote.set(zmq::sockopt::linger, 0);
  sockets_->remote.set(zmq::sockopt::rcvtimeo, 20);
  sockets_->pub.set(zmq::sockopt::linger, 0);
  sockets_->remote.bind("tcp://127.0.0.1:*");
  sockets_->pub.bind("tcp://127.0.0.1:*");
  remote_port_ = bound_port(sockets_->remote);
  pub_port_ = bound_port(sockets_->pub);
  remote_thread_ = std::thread([this] { remote_loop(); });
}

PupilCaptureEmulator::~PupilCaptureEmulator() {
  stopping_ = true;
  stop_publishing();
  if (remote_thread_.joinable()) remote_thread_.join();
}

void PupilCaptureEmulator::remote_loop() {
  while (!stopping_) {
    zmq::message_t request;
    if (!sockets_->remote.recv(request, zmq::recv_flags::none)) continue;
    const std::string text = request.to_string();
    if (silent_) {
      // A REP socket must answer before it can receive again; a gone tracker answers nothing, so
      // wait until the silence ends and answer the stale request (the client has given up on it).
      while (silent_ && !stopping_) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    std::string reply;
    if (text == "SUB_PORT") {
      reply = std::to_string(pub_port_);
    } else if (text == "t") {
      ++time_requests_;
      TimeReply scripted;
      {
        const std::lock_guard lock(mutex_);
        scripted.delay_s = t_delay_s_;
        if (!time_replies_.empty()) {
          scripted = time_replies_.front();
          time_replies_.erase(time_replies_.begin());
        }
      }
      if (scripted.delay_s > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(scripted.delay_s));
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "%.9f", steady_now_s() + pupil_time_offset_s_);
      reply = scripted.text.empty() ? std::string(buffer) : scripted.text;
    } else if (!text.empty() && text[0] == 'T') {
      ++time_set_requests_;
      reply = "Timesync successful.";
    } else {
      reply = "Unknown command.";
    }
    sockets_->remote.send(zmq::buffer(reply), zmq::send_flags::none);
  }
}

void PupilCaptureEmulator::script_time_replies(std::vector<TimeReply> replies, double t_delay_s) {
  const std::lock_guard lock(mutex_);
  time_replies_ = std::move(replies);
  t_delay_s_ = t_delay_s;
}

void PupilCaptureEmulator::start_publishing(std::function<double(double)> diameter_mm,
                                            std::vector<std::pair<double, double>> blinks) {
  diameter_mm_ = std::move(diameter_mm);
  blinks_ = std::move(blinks);
  publishing_ = true;
  publish_thread_ = std::thread([this] { publish_loop(); });
}

void PupilCaptureEmulator::stop_publishing() {
  publishing_ = false;
  if (publish_thread_.joinable()) publish_thread_.join();
}

void PupilCaptureEmulator::publish_raw(const std::string& topic, const std::string& payload) {
  const std::lock_guard lock(mutex_);
  sockets_->pub.send(zmq::buffer(topic), zmq::send_flags::sndmore);
  sockets_->pub.send(zmq::buffer(payload), zmq::send_flags::none);
}

void PupilCaptureEmulator::publish_blink(bool onset) {
  publish_raw("blinks", pack_blink(steady_now_s() + pupil_time_offset_s_, onset));
}

void PupilCaptureEmulator::publish_loop() {
  const auto start = std::chrono::steady_clock::now();
  const double start_s = steady_now_s();
  std::int64_t k = 0;
  std::size_t blink_state = 0;  // 2 * blink index + (1 when inside)
  while (publishing_) {
    std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                              std::chrono::duration<double>(static_cast<double>(k) / rate_hz_)));
    ++k;
    if (silent_) continue;
    const double now_s = steady_now_s();
    const double since_s = now_s - start_s;
    const double pupil_time_s = now_s + pupil_time_offset_s_;
    bool blinking = false;
    for (const auto& [begin, end] : blinks_) blinking = blinking || (since_s >= begin && since_s < end);
    const std::lock_guard lock(mutex_);
    // Blink onset/offset messages when the scripted state changes.
    if (blinking != (blink_state % 2 == 1)) {
      ++blink_state;
      sockets_->pub.send(zmq::buffer(std::string("blinks")), zmq::send_flags::sndmore);
      sockets_->pub.send(zmq::buffer(pack_blink(pupil_time_s, blinking)), zmq::send_flags::none);
    }
    for (int eye = 0; eye < 2; ++eye) {
      EmulatedPupilDatum datum;
      datum.eye = eye;
      datum.pupil_time_s = pupil_time_s;
      datum.diameter_mm = blinking ? 0.0 : diameter_mm_(since_s) + (eye == 0 ? 0.0 : 0.1);
      datum.confidence = blinking ? 0.0 : 0.97;
      const std::string topic = "pupil." + std::to_string(eye) + ".3d";
      sockets_->pub.send(zmq::buffer(topic), zmq::send_flags::sndmore);
      sockets_->pub.send(zmq::buffer(pack_pupil(eye, datum.pupil_time_s, datum.diameter_mm, datum.confidence)),
                         zmq::send_flags::none);
      published_.push_back(datum);
    }
    sockets_->pub.send(zmq::buffer(std::string("gaze.3d.01.")), zmq::send_flags::sndmore);
    sockets_->pub.send(zmq::buffer(pack_gaze(pupil_time_s, 0.25, 0.75, blinking ? 0.0 : 0.9)), zmq::send_flags::none);
  }
}

std::vector<EmulatedPupilDatum> PupilCaptureEmulator::published() const {
  const std::lock_guard lock(mutex_);
  return published_;
}

}  // namespace glarelab::test
