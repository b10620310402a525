#include "runner/tracker/clock_offset.h"

#include <algorithm>
#include <stdexcept>

namespace glarelab {

ClockOffsetEstimate estimate_clock_offset(std::vector<RoundTrip> trips, std::size_t fastest) {
  if (trips.empty()) throw std::invalid_argument("estimate_clock_offset: no round trips");
  std::sort(trips.begin(), trips.end(),
            [](const RoundTrip& a, const RoundTrip& b) { return a.round_trip_s() < b.round_trip_s(); });
  const std::size_t used = std::clamp<std::size_t>(fastest, 1, trips.size());
  std::vector<double> offsets;
  for (std::size_t i = 0; i < used; ++i) offsets.push_back(trips[i].offset_s());
  std::sort(offsets.begin(), offsets.end());
  ClockOffsetEstimate estimate;
  estimate.offset_s = used % 2 == 1 ? offsets[used / 2] : 0.5 * (offsets[used / 2 - 1] + offsets[used / 2]);
  estimate.fastest_round_trip_s = trips.front().round_trip_s();
  estimate.uncertainty_s = 0.5 * trips[used - 1].round_trip_s();
  estimate.round_trips = trips.size();
  return estimate;
}

}  // namespace glarelab
