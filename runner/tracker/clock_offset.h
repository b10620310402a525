#pragma once
// Offset between a tracker's clock and the session clock from request/reply round trips
// (Cristian's method): for each round trip, offset = device time - midpoint of the local send and
// receive times. The error of one estimate is bounded by half its round trip, so only the fastest
// round trips are used: the estimate is the median of the offsets of the `fastest` quickest trips.
#include <cstddef>
#include <vector>

namespace glarelab {

struct RoundTrip {
  double local_send_s = 0.0;
  double device_time_s = 0.0;
  double local_receive_s = 0.0;
  double round_trip_s() const { return local_receive_s - local_send_s; }
  double offset_s() const { return device_time_s - 0.5 * (local_send_s + local_receive_s); }
};

struct ClockOffsetEstimate {
  double offset_s = 0.0;             // device time - session time
  double uncertainty_s = 0.0;        // half the fastest round trip used (bound on the error)
  double fastest_round_trip_s = 0.0;
  std::size_t round_trips = 0;
};

// Throws std::invalid_argument for no round trips.
ClockOffsetEstimate estimate_clock_offset(std::vector<RoundTrip> trips, std::size_t fastest = 3);

}  // namespace glarelab
