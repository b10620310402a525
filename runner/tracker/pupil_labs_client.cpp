#include "runner/tracker/pupil_labs_client.h"

#include <msgpack.hpp>
#include <zmq.hpp>
#include <zmq_addon.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

#include "core/clock.h"

namespace glarelab {

namespace {

int milliseconds(double seconds) { return std::max(1, static_cast<int>(std::lround(seconds * 1000.0))); }

const msgpack::object* find_key(const msgpack::object& map, const char* key) {
  const std::size_t length = std::strlen(key);
  for (std::uint32_t i = 0; i < map.via.map.size; ++i) {
    const msgpack::object& k = map.via.map.ptr[i].key;
    if (k.type == msgpack::type::STR && k.via.str.size == length && std::memcmp(k.via.str.ptr, key, length) == 0)
      return &map.via.map.ptr[i].val;
  }
  return nullptr;
}

std::optional<double> number(const msgpack::object* value) {
  if (value == nullptr) return std::nullopt;
  double out = 0.0;
  switch (value->type) {
    case msgpack::type::FLOAT64:
    case msgpack::type::FLOAT32: out = value->via.f64; break;
    case msgpack::type::POSITIVE_INTEGER: out = static_cast<double>(value->via.u64); break;
    case msgpack::type::NEGATIVE_INTEGER: out = static_cast<double>(value->via.i64); break;
    default: return std::nullopt;
  }
  if (!std::isfinite(out)) return std::nullopt;
  return out;
}

std::optional<std::string> text(const msgpack::object* value) {
  if (value == nullptr || value->type != msgpack::type::STR) return std::nullopt;
  return std::string(value->via.str.ptr, value->via.str.size);
}

// A REQ socket with timeouts and no lingering; a REQ socket whose request timed out is unusable
// (its state machine waits for the lost reply), so callers make a new one after a timeout.
zmq::socket_t make_request_socket(zmq::context_t& context, const std::string& endpoint, double timeout_s) {
  zmq::socket_t socket(context, zmq::socket_type::req);
  socket.set(zmq::sockopt::linger, 0);
  socket.set(zmq::sockopt::rcvtimeo, milliseconds(timeout_s));
  socket.set(zmq::sockopt::sndtimeo, milliseconds(timeout_s));
  socket.connect(endpoint);
  return socket;
}

std::optional<std::string> request(zmq::socket_t& socket, const std::string& message) {
  if (!socket.send(zmq::buffer(message), zmq::send_flags::none)) return std::nullopt;
  zmq::message_t reply;
  if (!socket.recv(reply, zmq::recv_flags::none)) return std::nullopt;
  return reply.to_string();
}

std::optional<int> parse_port(const std::string& reply) {
  char* end = nullptr;
  const long port = std::strtol(reply.c_str(), &end, 10);
  if (reply.empty() || *end != '\0' || port <= 0 || port > 65535) return std::nullopt;
  return static_cast<int>(port);
}

std::string endpoint(const std::string& host, int port) { return "tcp://" + host + ":" + std::to_string(port); }

}  // namespace

PupilLabsSettings parse_pupil_labs_address(const std::string& spec) {
  const std::string scheme = "pupil-labs://";
  if (!spec.starts_with(scheme))
    throw TrackerError("--tracker " + spec + ": expected pupil-labs://HOST:PORT");
  PupilLabsSettings settings;
  const std::string address = spec.substr(scheme.size());
  const auto colon = address.rfind(':');
  settings.host = colon == std::string::npos ? address : address.substr(0, colon);
  if (colon != std::string::npos) {
    const auto port = parse_port(address.substr(colon + 1));
    if (!port) throw TrackerError("--tracker " + spec + ": '" + address.substr(colon + 1) + "' is not a port (1-65535)");
    settings.port = *port;
  }
  if (settings.host.empty()) throw TrackerError("--tracker " + spec + ": no host");
  // ZeroMQ takes a host name, an IPv4 address or a bracketed IPv6 one in its endpoint; anything
  // else ("a b", "*", which binds every interface) it refuses with an exception of its own when the
  // session connects: refused here, as bad input, before anything is written.
  const std::string& host = settings.host;
  const bool bracketed = host.size() > 2 && host.front() == '[' && host.back() == ']';
  const auto allowed = [&](char c) {
    const bool name = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-';
    return bracketed ? name || c == ':' : name || c == '_';
  };
  const std::string inner = bracketed ? host.substr(1, host.size() - 2) : host;
  if (!std::all_of(inner.begin(), inner.end(), allowed) || inner.front() == '-' || inner.front() == '.')
    throw TrackerError("--tracker " + spec + ": '" + host +
                       "' is not a host (a name, an IPv4 address or a bracketed IPv6 address such as [::1])");
  return settings;
}

std::optional<PupilLabsMessage> decode_pupil_labs_message(const std::string& topic, const void* payload,
                                                          std::size_t payload_bytes) {
  try {
    // msgpack allocates an array's or map's elements when it reads the declared count, before the
    // elements themselves: without a limit a 74-byte message declaring 0x08008ca2 elements made it
    // allocate 4 GB (found by fuzz/pupil_labs_fuzzer.cpp). Each element takes at least one byte
    // (a map pair two) and a string or binary at most the payload, so no valid message declares
    // more than payload_bytes of anything; a larger count is refused (unpack throws).
    const msgpack::unpack_limit limit(payload_bytes, payload_bytes / 2, payload_bytes, payload_bytes, payload_bytes);
    const msgpack::object_handle handle =
        msgpack::unpack(static_cast<const char*>(payload), payload_bytes, nullptr, nullptr, limit);
    const msgpack::object& root = handle.get();
    if (root.type != msgpack::type::MAP) return std::nullopt;
    PupilLabsMessage message;
    const auto timestamp = number(find_key(root, "timestamp"));
    const auto confidence = number(find_key(root, "confidence"));
    if (!timestamp || !confidence || *confidence < 0.0 || *confidence > 1.0) return std::nullopt;
    message.timestamp_s = *timestamp;
    message.confidence = *confidence;
    if (topic == "pupil.0.3d" || topic == "pupil.1.3d") {
      message.kind = PupilLabsMessage::Kind::pupil;
      const auto id = number(find_key(root, "id"));
      const auto diameter = number(find_key(root, "diameter_3d"));
      const int topic_eye = topic[6] - '0';
      if (!id || *id != topic_eye || !diameter || *diameter < 0.0) return std::nullopt;
      message.eye = topic_eye;
      message.diameter_3d_mm = *diameter;
      return message;
    }
    if (topic.starts_with("gaze.3d.")) {
      message.kind = PupilLabsMessage::Kind::gaze;
      const msgpack::object* norm_pos = find_key(root, "norm_pos");
      if (norm_pos == nullptr || norm_pos->type != msgpack::type::ARRAY || norm_pos->via.array.size != 2)
        return std::nullopt;
      const auto x = number(&norm_pos->via.array.ptr[0]);
      const auto y = number(&norm_pos->via.array.ptr[1]);
      if (!x || !y) return std::nullopt;
      message.norm_x = *x;
      message.norm_y = *y;
      return message;
    }
    if (topic == "blinks") {
      message.kind = PupilLabsMessage::Kind::blink;
      const auto type = text(find_key(root, "type"));
      if (!type || (*type != "onset" && *type != "offset")) return std::nullopt;
      message.blink_onset = *type == "onset";
      return message;
    }
    return std::nullopt;
  } catch (const std::exception&) {
    return std::nullopt;  // msgpack::unpack_error, type errors: a malformed payload
  }
}

std::optional<int> probe_pupil_remote(const std::string& host, int port, double timeout_s) {
  try {
    zmq::context_t context(1);
    zmq::socket_t socket = make_request_socket(context, endpoint(host, port), timeout_s);
    const auto reply = request(socket, "SUB_PORT");
    if (!reply) return std::nullopt;
    return parse_port(*reply);
  } catch (const zmq::error_t&) {
    return std::nullopt;
  }
}

struct PupilLabsClient::Connection {
  zmq::context_t context{1};
  std::optional<zmq::socket_t> remote;  // REQ to Pupil Remote
  std::optional<zmq::socket_t> sub;     // SUB to the IPC backbone
};

PupilLabsClient::PupilLabsClient(PupilLabsSettings settings)
    : settings_(std::move(settings)), connection_(std::make_unique<Connection>()) {}

PupilLabsClient::~PupilLabsClient() { stop(); }

std::string PupilLabsClient::description() const {
  return "pupil-labs://" + settings_.host + ":" + std::to_string(settings_.port);
}

TrackerStatus PupilLabsClient::status() const {
  const std::lock_guard lock(status_mutex_);
  return status_;
}

ClockOffsetEstimate PupilLabsClient::clock_offset() const {
  const std::lock_guard lock(status_mutex_);
  return offset_;
}

std::optional<ClockOffsetEstimate> PupilLabsClient::measure_offset(zmq::socket_t& remote, TrackerBatch& batch,
                                                                   std::string* why) {
  std::vector<RoundTrip> trips;
  std::vector<std::string> faults;
  for (int i = 0; i < settings_.offset_round_trips; ++i) {
    RoundTrip trip;
    trip.local_send_s = clock_->now_s();
    const auto reply = request(remote, "t");
    trip.local_receive_s = clock_->now_s();
    if (!reply) {
      *why = description() + ": Pupil Remote stopped answering 't'";
      return std::nullopt;
    }
    // strtod reads "nan" and "inf" as numbers: a time that is not finite is a fault, not a time.
    char* end = nullptr;
    trip.device_time_s = std::strtod(reply->c_str(), &end);
    if (reply->empty() || *end != '\0' || !std::isfinite(trip.device_time_s)) {
      faults.push_back(reply->substr(0, 32));
      continue;
    }
    trips.push_back(trip);
  }
  if (!faults.empty()) {
    std::int64_t count = 0;
    {
      const std::lock_guard lock(status_mutex_);
      count = status_.clock_faults += static_cast<std::int64_t>(faults.size());
    }
    batch.notices.push_back({clock_->now_s(), "tracker_clock_fault",
                             description() + ": " + std::to_string(faults.size()) + " of " +
                                 std::to_string(settings_.offset_round_trips) + " 't' replies were not a time (first '" +
                                 faults.front() + "'), skipped; " + std::to_string(count) + " so far"});
  }
  // Fewer than half the trips answered with a time: the estimate would rest on too few of them.
  if (2 * trips.size() < static_cast<std::size_t>(settings_.offset_round_trips)) {
    *why = description() + ": 't' answered '" + (faults.empty() ? std::string() : faults.front()) +
           "', not a time, in " + std::to_string(faults.size()) + " of " + std::to_string(settings_.offset_round_trips) +
           " requests";
    return std::nullopt;
  }
  const ClockOffsetEstimate estimate = estimate_clock_offset(trips);
  const std::lock_guard lock(status_mutex_);
  offset_ = estimate;
  return estimate;
}

bool PupilLabsClient::connect(std::string* why) {
  Connection& c = *connection_;
  c.sub.reset();
  c.remote.emplace(make_request_socket(c.context, endpoint(settings_.host, settings_.port), settings_.request_timeout_s));
  const auto reply = request(*c.remote, "SUB_PORT");
  if (!reply) {
    *why = "no Pupil Remote answers at " + settings_.host + ":" + std::to_string(settings_.port) + " (waited " +
           std::to_string(settings_.request_timeout_s) + " s for SUB_PORT)";
    c.remote.reset();
    return false;
  }
  const auto sub_port = parse_port(*reply);
  if (!sub_port) {
    *why = "Pupil Remote answered SUB_PORT with '" + *reply + "'";
    c.remote.reset();
    return false;
  }
  TrackerBatch notices;
  const bool measured = measure_offset(*c.remote, notices, why).has_value();
  queue_.push(std::move(notices));
  c.remote.reset();  // from here on "t" goes through the clock thread's own socket
  if (!measured) return false;
  c.sub.emplace(c.context, zmq::socket_type::sub);
  c.sub->set(zmq::sockopt::linger, 0);
  c.sub->set(zmq::sockopt::rcvtimeo, 50);
  for (const char* topic : {"pupil.0.3d", "pupil.1.3d", "gaze.3d.", "blinks"}) c.sub->set(zmq::sockopt::subscribe, topic);
  c.sub->connect(endpoint(settings_.host, *sub_port));
  return true;
}

void PupilLabsClient::start(const SessionClock& clock) {
  clock_ = &clock;
  std::string why;
  if (!connect(&why)) throw TrackerError("tracker " + description() + ": " + why);
  stopping_ = false;
  connected_ = true;
  thread_ = std::thread([this] { receive_loop(); });
  clock_thread_ = std::thread([this] { clock_loop(); });
}

void PupilLabsClient::stop() {
  stopping_ = true;
  if (thread_.joinable()) thread_.join();
  if (clock_thread_.joinable()) clock_thread_.join();
  connection_->sub.reset();
  connection_->remote.reset();
}

// The periodic clock re-estimate runs on its own thread with its own Pupil Remote socket: a slow
// 't' (each may take up to request_timeout_s, offset_round_trips of them) must never hold up the
// receiver, whose SUB queue would otherwise overflow and drop samples unseen. A failed estimate
// keeps the last offset and is logged; the connection itself is judged by the data stream.
void PupilLabsClient::clock_loop() {
  const std::string address = endpoint(settings_.host, settings_.port);
  std::optional<zmq::socket_t> remote;
  double next_offset_s = clock_->now_s() + settings_.offset_interval_s;
  while (!stopping_) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    const double now_s = clock_->now_s();
    if (!connected_) next_offset_s = now_s + settings_.offset_interval_s;  // connect() measures afresh
    if (now_s < next_offset_s) continue;
    if (!remote) remote.emplace(make_request_socket(connection_->context, address, settings_.request_timeout_s));
    TrackerBatch batch;
    std::string why;
    if (const auto estimate = measure_offset(*remote, batch, &why)) {
      std::ostringstream note;
      note.precision(9);
      note << "offset " << estimate->offset_s << " s (+/- " << estimate->uncertainty_s << " s, fastest round trip "
           << estimate->fastest_round_trip_s << " s)";
      batch.notices.push_back({clock_->now_s(), "tracker_clock", note.str()});
    } else {
      remote.reset();  // a REQ socket whose request timed out is unusable
      batch.notices.push_back({clock_->now_s(), "tracker_clock_fault", why + "; the last offset is kept"});
    }
    queue_.push(std::move(batch));
    next_offset_s = clock_->now_s() + settings_.offset_interval_s;
  }
}

TrackerBatch PupilLabsClient::poll(double) { return queue_.take_all(); }

void PupilLabsClient::handle(const std::string& topic, const void* payload, std::size_t bytes, TrackerBatch& batch) {
  const auto message = decode_pupil_labs_message(topic, payload, bytes);
  if (!message) {
    std::int64_t count = 0;
    {
      const std::lock_guard lock(status_mutex_);
      count = ++status_.malformed_messages;
    }
    // The first and then every 100th: enough to see it happen without flooding the log.
    if (count == 1 || count % 100 == 0)
      batch.notices.push_back({clock_->now_s(), "tracker_malformed",
                               std::to_string(count) + " malformed message(s) skipped so far (latest topic '" +
                                   topic.substr(0, 64) + "')"});
    return;
  }
  const double offset_s = clock_offset().offset_s;
  switch (message->kind) {
    case PupilLabsMessage::Kind::gaze: latest_gaze_ = message; break;
    case PupilLabsMessage::Kind::blink:
      batch.blinks.push_back({message->timestamp_s - offset_s, message->blink_onset, message->confidence});
      break;
    case PupilLabsMessage::Kind::pupil: {
      TrackerSample sample;
      sample.eye = message->eye;
      sample.device_time_s = message->timestamp_s;
      sample.session_time_s = message->timestamp_s - offset_s;
      sample.pupil_diameter_mm = message->diameter_3d_mm;
      sample.confidence = message->confidence;
      sample.valid = message->confidence > 0.0 && message->diameter_3d_mm > 0.0;
      if (latest_gaze_ && std::abs(message->timestamp_s - latest_gaze_->timestamp_s) <= settings_.gaze_max_age_s) {
        // Pupil's norm_pos has its origin at the bottom left; display coordinates at the top left.
        sample.gaze_x = latest_gaze_->norm_x;
        sample.gaze_y = 1.0 - latest_gaze_->norm_y;
      }
      batch.samples.push_back(sample);
      const std::lock_guard lock(status_mutex_);
      ++status_.samples;
      break;
    }
  }
}

void PupilLabsClient::receive_loop() {
  bool connected = true;
  double last_message_s = clock_->now_s();
  // The longest silence of the data stream, across reconnections (a reconnect to a Remote whose
  // stream stays silent is not data).
  double last_data_s = last_message_s;
  const auto note_gap = [&](double now_s) {
    const std::lock_guard lock(status_mutex_);
    status_.longest_gap_s = std::max(status_.longest_gap_s, now_s - last_data_s);
  };
  double backoff_s = settings_.backoff_initial_s;
  double next_attempt_s = 0.0;
  while (!stopping_) {
    TrackerBatch batch;
    const double now_s = clock_->now_s();
    if (connected) {
      std::vector<zmq::message_t> parts;
      std::optional<std::size_t> received;
      try {
        received = zmq::recv_multipart(*connection_->sub, std::back_inserter(parts));
      } catch (const zmq::error_t&) {
        received.reset();
      }
      if (received) {
        last_message_s = clock_->now_s();
        note_gap(last_message_s);
        last_data_s = last_message_s;
        // [topic, payload] (Capture may append raw-data frames: ignored).
        if (parts.size() >= 2)
          handle(parts[0].to_string(), parts[1].data(), parts[1].size(), batch);
        else
          handle(parts.empty() ? std::string() : parts[0].to_string(), nullptr, 0, batch);
      }
      const double after_s = clock_->now_s();
      if (after_s - last_message_s > settings_.loss_timeout_s) {
        connected = false;
        connected_ = false;
        connection_->sub.reset();
        backoff_s = settings_.backoff_initial_s;
        next_attempt_s = after_s;
        {
          const std::lock_guard lock(status_mutex_);
          ++status_.connection_losses;
        }
        batch.notices.push_back({last_message_s, "tracker_lost",
                                 description() + ": connection lost (no message for " +
                                     std::to_string(after_s - last_message_s) + " s)"});
      }
    } else if (now_s >= next_attempt_s) {
      std::string why;
      if (connect(&why)) {
        connected = true;
        connected_ = true;
        const double gap_s = clock_->now_s() - last_message_s;
        last_message_s = clock_->now_s();
        {
          const std::lock_guard lock(status_mutex_);
          ++status_.reconnections;
        }
        batch.notices.push_back({last_message_s, "tracker_reconnected",
                                 description() + ": reconnected after a gap of " + std::to_string(gap_s) + " s"});
      } else {
        next_attempt_s = now_s + backoff_s;
        backoff_s = std::min(2.0 * backoff_s, settings_.backoff_max_s);
      }
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    queue_.push(std::move(batch));
  }
  note_gap(clock_->now_s());  // a stream still silent at the end
}

}  // namespace glarelab
