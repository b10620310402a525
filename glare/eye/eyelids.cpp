#include "glare/eye/eyelids.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "glare/eye/eye_random_channels.h"
#include "core/random.h"

namespace glarelab {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kClosedOverlapMm = 0.2;
constexpr int kMarginSegments = 32;
constexpr double kLidHalfWidthMm = 8.0;  // polygons reach past the 9 mm aperture on every side
constexpr double kLidFarEdgeMm = 16.0;

double half_cosine(double s) { return 0.5 * (1.0 - std::cos(kPi * std::clamp(s, 0.0, 1.0))); }
}  // namespace

EyelidModel::EyelidModel(const EyeParameters& p, std::uint64_t seed)
    : parameters_(p),
      seed_(seed),
      closing_s_(p.blink_closing_duration_s),
      closed_s_(p.blink_closed_duration_s),
      opening_s_(p.blink_opening_duration_s),
      interval_s_(p.blink_mean_interval_s) {
  const CounterRandom random(seed, RandomStream::eye_model);
  const auto sub = [](std::uint32_t k) { return eye_sub_index(EyeChannel::eyelashes, k); };
  const int total = p.upper_eyelash_count + p.lower_eyelash_count;
  for (int k = 0; k < total; ++k) {
    const auto index = static_cast<std::uint64_t>(k);
    const bool upper = k < p.upper_eyelash_count;
    const double reach = upper ? p.upper_eyelash_overhang_max_mm : p.lower_eyelash_overhang_max_mm;
    lashes_.push_back(Lash{p.eyelash_window_half_width_mm * (2.0 * random.uniform(index, sub(0)) - 1.0),
                           (kPi / 9.0) * (2.0 * random.uniform(index, sub(1)) - 1.0),  // +-20 degrees
                           reach * (0.2 + 0.8 * random.uniform(index, sub(2))), upper});
  }
}

double EyelidModel::blink_onset_s(std::int64_t index) const {
  const CounterRandom random(seed_, RandomStream::eye_model);
  const double u = random.uniform(static_cast<std::uint64_t>(index), eye_sub_index(EyeChannel::blinks, 0));
  return static_cast<double>(index) * interval_s_ + u * (interval_s_ - blink_duration_s());
}

void EyelidModel::set_recorded_blinks(std::vector<std::pair<double, double>> blinks) {
  for (std::size_t k = 0; k < blinks.size(); ++k) {
    const auto [onset_s, offset_s] = blinks[k];
    if (!std::isfinite(onset_s) || !(offset_s >= onset_s))
      throw std::invalid_argument("eyelids: a recorded blink needs a finite onset and an offset at or after it");
    if (k > 0 && onset_s < blinks[k - 1].first)
      throw std::invalid_argument("eyelids: recorded blinks must come in time order");
  }
  recorded_ = true;
  recorded_blinks_.clear();
  for (const auto& [onset_s, offset_s] : blinks) recorded_blinks_.push_back({onset_s, offset_s});
}

double EyelidModel::recorded_closure(const RecordedBlink& blink, double time_s) const {
  const double since = time_s - blink.onset_s;
  if (since < 0.0) return 0.0;
  if (since < closing_s_) return half_cosine(since / closing_s_);
  const double opening_from_s = std::max(blink.offset_s, blink.onset_s + closing_s_);
  if (time_s < opening_from_s) return 1.0;
  const double opening = time_s - opening_from_s;
  return opening >= opening_s_ ? 0.0 : 1.0 - half_cosine(opening / opening_s_);
}

double EyelidModel::blink_closure(double time_s) const {
  if (time_s < 0.0) return 0.0;
  if (recorded_) {
    // The last blink begun by time_s and the one before it (still opening when the next began).
    const auto after = std::upper_bound(recorded_blinks_.begin(), recorded_blinks_.end(), time_s,
                                        [](double t, const RecordedBlink& blink) { return t < blink.onset_s; });
    double closure = 0.0;
    for (auto it = after; it != recorded_blinks_.begin() && after - it < 2;) closure = std::max(closure, recorded_closure(*--it, time_s));
    return closure;
  }
  // Blinks never span two intervals, so only the interval holding time_s can be blinking.
  const auto index = static_cast<std::int64_t>(std::floor(time_s / interval_s_));
  const double since = time_s - blink_onset_s(index);
  if (since < 0.0 || since > blink_duration_s()) return 0.0;
  if (since < closing_s_) return half_cosine(since / closing_s_);
  if (since < closing_s_ + closed_s_) return 1.0;
  return 1.0 - half_cosine((since - closing_s_ - closed_s_) / opening_s_);
}

double EyelidModel::lid_closure(double time_s) const {
  const double squint = parameters_.squint_closure;
  return squint + (1.0 - squint) * blink_closure(time_s);
}

double EyelidModel::upper_margin_centre_mm(double closure) const {
  const double closed = parameters_.lid_meeting_height_mm - 0.5 * kClosedOverlapMm;
  return parameters_.upper_lid_open_margin_mm + closure * (closed - parameters_.upper_lid_open_margin_mm);
}

double EyelidModel::lower_margin_centre_mm(double closure) const {
  const double closed = parameters_.lid_meeting_height_mm + 0.5 * kClosedOverlapMm;
  return parameters_.lower_lid_open_margin_mm + closure * (closed - parameters_.lower_lid_open_margin_mm);
}

void EyelidModel::append_occluders(double closure, ApertureGeometry& geometry) const {
  const double curvature = 1.0 / (2.0 * parameters_.lid_margin_curvature_radius_mm);
  const double upper = upper_margin_centre_mm(closure), lower = lower_margin_centre_mm(closure);
  auto margin = [&](bool is_upper, double x) {
    return is_upper ? upper - curvature * x * x : lower + curvature * x * x;
  };
  for (const bool is_upper : {true, false}) {
    AperturePolygon lid;
    lid.transmittance = 0.0;
    lid.component = ApertureComponent::lids;
    for (int k = 0; k <= kMarginSegments; ++k) {
      const double x = -kLidHalfWidthMm + 2.0 * kLidHalfWidthMm * k / kMarginSegments;
      lid.vertices_mm.push_back(x);
      lid.vertices_mm.push_back(margin(is_upper, x));
    }
    const double far = is_upper ? kLidFarEdgeMm : -kLidFarEdgeMm;
    lid.vertices_mm.insert(lid.vertices_mm.end(), {kLidHalfWidthMm, far, -kLidHalfWidthMm, far});
    geometry.polygons.push_back(std::move(lid));
  }
  for (const Lash& lash : lashes_) {
    const double root_y = margin(lash.upper, lash.root_x_mm);
    const double direction = lash.upper ? -1.0 : 1.0;  // into the opening
    ApertureLine line;
    line.x0_mm = lash.root_x_mm;
    line.y0_mm = root_y;
    line.x1_mm = lash.root_x_mm + lash.overhang_mm * std::sin(lash.tilt_rad);
    line.y1_mm = root_y + direction * lash.overhang_mm * std::cos(lash.tilt_rad);
    line.width_mm = parameters_.eyelash_width_mm;
    line.transmittance = 0.0;
    line.component = ApertureComponent::lashes;
    geometry.lines.push_back(line);
  }
}

}  // namespace glarelab
