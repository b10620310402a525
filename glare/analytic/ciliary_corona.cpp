#include "glare/analytic/ciliary_corona.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/parallel_for.h"

namespace glarelab {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegPerRad = 180.0 / kPi;

// 0 at `zero`, 1 at `one`, a raised cosine between (either order).
double raised_cosine(double x, double zero, double one) {
  const double t = std::clamp((x - zero) / (one - zero), 0.0, 1.0);
  return 0.5 - 0.5 * std::cos(kPi * t);
}

// The semicircle density's cumulative distribution in units of its half width,
// F(u) = 1/2 + (u sqrt(1 - u^2) + asin u) / pi on [-1, 1], tabulated (linear between 4096 steps:
// within 3e-6 of the formula, worst at the ends where F grows as (1 + u)^(3/2)).
class SemicircleCdf {
 public:
  SemicircleCdf() {
    for (int i = 0; i <= kSteps; ++i) {
      const double u = std::clamp(-1.0 + 2.0 * i / kSteps, -1.0, 1.0);
      table_[static_cast<std::size_t>(i)] = 0.5 + (u * std::sqrt(std::max(0.0, 1.0 - u * u)) + std::asin(u)) / kPi;
    }
  }
  double operator()(double u) const {
    if (u <= -1.0) return 0.0;
    if (u >= 1.0) return 1.0;
    const double at = (u + 1.0) * (0.5 * kSteps);
    const auto i = std::min(static_cast<std::size_t>(at), static_cast<std::size_t>(kSteps - 1));
    const double t = at - static_cast<double>(i);
    return table_[i] + t * (table_[i + 1] - table_[i]);
  }

 private:
  static constexpr int kSteps = 4096;
  std::array<double, kSteps + 1> table_{};
};

const SemicircleCdf& semicircle_cdf() {
  static const SemicircleCdf table;
  return table;
}

// The lines in azimuth order, then the same lines again a turn on, so that a window of azimuths
// crossing 2 pi reads on through contiguous entries: no wrap test nor index modulo per line, which
// took about a third of the pattern's time. A line of the second copy is at (its azimuth - start)
// + 2 pi from the window's start, as the one copy with the wrap added gave it, bit for bit.
class LineTurns {
 public:
  explicit LineTurns(const std::vector<FlareLine>& lines) : count_(lines.size()) {
    azimuth_rad_.reserve(2 * count_);
    intensity_.reserve(2 * count_);
    turn_rad_.reserve(2 * count_);
    for (const double turn : {0.0, 2.0 * kPi})
      for (const FlareLine& line : lines) {
        azimuth_rad_.push_back(line.azimuth_rad);
        intensity_.push_back(line.intensity);
        turn_rad_.push_back(turn);
      }
  }

  // FlareLines::normalised (Spencer's closed form about a disc) with the tabulated semicircle, for
  // a line half width h and a disc half width b > 0 (radians of azimuth), h + b <= pi: each line's
  // box convolved with the semicircle, only the lines within h + b of the azimuth. `scale` is
  // pi / (h sum of the intensities): each blurred box holds 2h of azimuth, so the ring's mean is 1.
  double about_disc(double h, double b, double scale, double azimuth_rad) const {
    const SemicircleCdf& cdf = semicircle_cdf();
    const double reach = h + b;
    // The azimuth from atan2 is within pi of 0 and reach <= pi, so this is fmod's value.
    double start = azimuth_rad - reach;
    if (start < 0.0) start += 2.0 * kPi;
    const auto first_copy_end = azimuth_rad_.begin() + static_cast<std::ptrdiff_t>(count_);
    std::size_t index = static_cast<std::size_t>(std::lower_bound(azimuth_rad_.begin(), first_copy_end, start) -
                                                 azimuth_rad_.begin());
    const std::size_t end = index + count_;  // at most one turn
    double sum = 0.0;
    const double inverse_b = 1.0 / b, window = 2.0 * reach;
    for (; index < end; ++index) {
      const double ahead = (azimuth_rad_[index] - start) + turn_rad_[index];
      if (ahead > window) break;
      const double y = reach - ahead;  // the azimuth less the line's, in [-reach, reach]
      sum += intensity_[index] * (cdf((y + h) * inverse_b) - cdf((y - h) * inverse_b));
    }
    return sum * scale;
  }

 private:
  std::size_t count_;
  std::vector<double> azimuth_rad_, intensity_, turn_rad_;
};

// What depends on the distance from the source alone, per source at kRadialSteps per pixel (read
// linearly between): K a, and the half widths h of a line and b of the disc (radians of azimuth).
constexpr int kRadialSteps = 8;
struct Radial {
  double smooth = 0.0, h = 0.0, b = 0.0;
};

}  // namespace

double corona_annulus_weight(double angle_deg) {
  if (angle_deg <= kCoronaInnerEdgeDeg || angle_deg >= kCoronaOuterEdgeDeg) return 0.0;
  if (angle_deg < kCoronaInnerDeg) return raised_cosine(angle_deg, kCoronaInnerEdgeDeg, kCoronaInnerDeg);
  if (angle_deg > kCoronaOuterDeg) return raised_cosine(angle_deg, kCoronaOuterEdgeDeg, kCoronaOuterDeg);
  return 1.0;
}

double corona_source_weight(double source_diameter_deg) {
  if (source_diameter_deg <= kCoronaFadeFromSourceDeg) return 1.0;
  if (source_diameter_deg >= kCoronaLargestSourceDeg) return 0.0;
  return raised_cosine(source_diameter_deg, kCoronaLargestSourceDeg, kCoronaFadeFromSourceDeg);
}

CiliaryCorona::CiliaryCorona(const ObserverEye& eye, const DisplayGeometry& geometry, std::uint64_t seed)
    : psf_(AnalyticPsf::cie(eye)), geometry_(geometry), lines_(FlareLineSet::corona, seed) {
  if (!(geometry.viewing_distance_mm > 0.0) || !(geometry.pixel_pitch_mm > 0.0))
    throw std::invalid_argument("glare/analytic/ciliary_corona: the display needs a positive distance and pitch");
  degrees_per_pixel_ = std::atan(geometry.pixel_pitch_mm / geometry.viewing_distance_mm) * kDegPerRad;
}

CompactSourceRule CiliaryCorona::source_rule() const {
  CompactSourceRule rule;
  rule.largest_diameter_px = kCoronaLargestSourceDeg / degrees_per_pixel_;
  return rule;
}

double CiliaryCorona::source_diameter_deg(const CompactSource& source) const {
  return source.disc_diameter_px() * degrees_per_pixel_;
}

double CiliaryCorona::blur_diameter_deg(const CompactSource& source) const {
  // Tangential variances add: a disc of diameter s has s^2 / 16, the source's second moment M2 / 2
  // (isotropic), the receiving pixel's square 1 / 12; so s^2 = 8 M2 + 4 / 3.
  return std::sqrt(8.0 * source.second_moment_px2 + 4.0 / 3.0) * degrees_per_pixel_;
}

std::shared_ptr<const CiliaryCorona::Pattern> CiliaryCorona::make_pattern(const CompactSource& source, int width_px,
                                                                          int height_px, int threads) const {
  const double share = corona_source_weight(source_diameter_deg(source));
  if (!(share > 0.0)) return nullptr;
  const double d = geometry_.viewing_distance_mm, pitch = geometry_.pixel_pitch_mm;
  const double inner_px = d * std::tan(kCoronaInnerEdgeDeg / kDegPerRad) / pitch;
  const double outer_px = d * std::tan(kCoronaOuterEdgeDeg / kDegPerRad) / pitch;
  const int x0 = static_cast<int>(std::floor(source.x_px - outer_px)), x1 = static_cast<int>(std::ceil(source.x_px + outer_px));
  const int y0 = static_cast<int>(std::floor(source.y_px - outer_px)), y1 = static_cast<int>(std::ceil(source.y_px + outer_px));
  // Nothing of the annulus on the frame: nothing to add.
  if (x1 < 0 || y1 < 0 || x0 >= width_px || y0 >= height_px) return nullptr;
  // Only the rings that reach the frame's pixels are made (each of them whole).
  const double near_x = std::clamp(source.x_px, 0.0, width_px - 1.0) - source.x_px;
  const double near_y = std::clamp(source.y_px, 0.0, height_px - 1.0) - source.y_px;
  const double far_x = std::max(source.x_px, width_px - 1.0 - source.x_px);
  const double far_y = std::max(source.y_px, height_px - 1.0 - source.y_px);
  const double ring_from_px = std::max(inner_px, std::floor(std::hypot(near_x, near_y)) - 1.0);
  const double ring_to_px = std::min(outer_px, std::ceil(std::hypot(far_x, far_y)) + 1.0);
  if (ring_from_px >= ring_to_px) return nullptr;
  const int side_x = x1 - x0 + 1, side_y = y1 - y0 + 1;
  const double blur_deg = blur_diameter_deg(source);
  double intensity_sum = 0.0;
  for (const FlareLine& line : lines_.lines()) intensity_sum += line.intensity;
  const double half_blur_sin = std::sin(0.5 * blur_deg / kDegPerRad);
  // The radial table from ring_from_px to ring_to_px.
  const int steps = static_cast<int>(std::ceil((ring_to_px - ring_from_px) * kRadialSteps)) + 1;
  std::vector<Radial> radial(static_cast<std::size_t>(steps) + 1);
  bool wraps = false;
  for (int i = 0; i <= steps; ++i) {
    const double r_px = ring_from_px + static_cast<double>(i) / kRadialSteps;
    const double squared = d * d + r_px * r_px * pitch * pitch;
    const double angle_deg = std::atan(r_px * pitch / d) * kDegPerRad, sin_theta = r_px * pitch / std::sqrt(squared);
    Radial& at = radial[static_cast<std::size_t>(i)];
    at.smooth = psf_.per_sr(angle_deg, 1) * d * pitch * pitch / (squared * std::sqrt(squared)) * corona_annulus_weight(angle_deg);
    at.h = 0.5 * kFlareLineWidthDeg / kDegPerRad / sin_theta;
    at.b = std::asin(std::min(1.0, half_blur_sin / sin_theta));
    wraps = wraps || (at.smooth > 0.0 && at.h + at.b > kPi);
  }
  if (wraps)  // never on the annulus: a source under 1 degree lies within 2 degrees' arc at 1.5 degrees
    throw std::logic_error("glare/analytic/ciliary_corona: a source's lines cover the whole ring on the annulus");
  // K a and K a L_s per offset of the square around the source (0 outside the annulus), rows in
  // parallel; then the rings' sums in one pass in row order, so nothing depends on `threads`.
  std::vector<double> smooth(static_cast<std::size_t>(side_x) * side_y, 0.0), lined(smooth.size(), 0.0);
  std::vector<int> ring(smooth.size(), -1);
  const LineTurns turns(lines_.lines());
  parallel_chunks(side_y, threads, [&](int first, int last) {
    for (int row = first; row < last; ++row) {
      const double dy = y0 + row - source.y_px;
      for (int col = 0; col < side_x; ++col) {
        const double dx = x0 + col - source.x_px;
        const double r_px = std::sqrt(dx * dx + dy * dy);
        if (r_px <= ring_from_px || r_px >= ring_to_px) continue;
        const double t = (r_px - ring_from_px) * kRadialSteps;
        const auto i = std::min(static_cast<std::size_t>(t), radial.size() - 2);
        const double f = t - static_cast<double>(i);
        const Radial& a = radial[i];
        const Radial& b = radial[i + 1];
        const double smooth_here = a.smooth + f * (b.smooth - a.smooth);
        if (!(smooth_here > 0.0)) continue;
        const double h = a.h + f * (b.h - a.h);
        const std::size_t at = static_cast<std::size_t>(row) * side_x + col;
        smooth[at] = smooth_here;
        lined[at] = smooth_here * turns.about_disc(h, a.b + f * (b.b - a.b), kPi / (h * intensity_sum), std::atan2(dy, dx));
        ring[at] = static_cast<int>(std::lround(r_px));
      }
    }
  });
  const int rings = static_cast<int>(std::ceil(outer_px)) + 2;
  std::vector<double> ring_smooth(static_cast<std::size_t>(rings), 0.0), ring_lined(ring_smooth.size(), 0.0);
  for (std::size_t i = 0; i < smooth.size(); ++i)
    if (ring[i] >= 0) {
      ring_smooth[static_cast<std::size_t>(ring[i])] += smooth[i];
      ring_lined[static_cast<std::size_t>(ring[i])] += lined[i];
    }
  // C = K a (L_s / m_k - 1), m_k the ring's K a-weighted mean of L_s, times the source's share.
  std::vector<double> scale(ring_smooth.size(), 0.0);
  for (std::size_t k = 0; k < scale.size(); ++k)
    if (ring_lined[k] > 0.0) scale[k] = ring_smooth[k] / ring_lined[k];
  auto pattern = std::make_shared<Pattern>();
  pattern->x_px = source.x_px;
  pattern->y_px = source.y_px;
  pattern->second_moment_px2 = source.second_moment_px2;
  pattern->width_px = width_px;
  pattern->height_px = height_px;
  pattern->from_y = std::max(0, y0), pattern->to_y = std::min(height_px - 1, y1);
  pattern->from_x = std::max(0, x0), pattern->to_x = std::min(width_px - 1, x1);
  const int columns = pattern->to_x - pattern->from_x + 1;
  const std::size_t covered = static_cast<std::size_t>(columns) * static_cast<std::size_t>(pattern->to_y - pattern->from_y + 1);
  pattern->c.assign(covered, 0.0);
  pattern->adds.assign(covered, 0);
  for (int y = pattern->from_y; y <= pattern->to_y; ++y)
    for (int x = pattern->from_x; x <= pattern->to_x; ++x) {
      const std::size_t at = static_cast<std::size_t>(y - y0) * side_x + (x - x0);
      if (ring[at] < 0 || scale[static_cast<std::size_t>(ring[at])] == 0.0) continue;
      const std::size_t here = static_cast<std::size_t>(y - pattern->from_y) * columns + (x - pattern->from_x);
      pattern->c[here] = share * (lined[at] * scale[static_cast<std::size_t>(ring[at])] - smooth[at]);
      pattern->adds[here] = 1;
    }
  return pattern;
}

CompactSource CiliaryCorona::pattern_key(const CompactSource& source) {
  CompactSource key = source;
  key.x_px = std::round(source.x_px * kPatternStepsPerPx) / kPatternStepsPerPx;
  key.y_px = std::round(source.y_px * kPatternStepsPerPx) / kPatternStepsPerPx;
  key.second_moment_px2 = std::round(source.second_moment_px2 * kPatternStepsPerPx) / kPatternStepsPerPx;
  return key;
}

std::shared_ptr<const CiliaryCorona::Pattern> CiliaryCorona::pattern(const CompactSource& met, int width_px,
                                                                     int height_px, int threads) const {
  const CompactSource source = pattern_key(met);
  {
    const std::lock_guard lock(patterns_->mutex);
    auto& recent = patterns_->recent;
    for (auto kept = recent.begin(); kept != recent.end(); ++kept)
      if ((*kept)->is_of(source, width_px, height_px)) {
        std::shared_ptr<const Pattern> found = *kept;
        recent.erase(kept);
        recent.push_front(found);  // the most recently used first
        return found;
      }
  }
  std::shared_ptr<const Pattern> made = make_pattern(source, width_px, height_px, threads);
  if (!made) return nullptr;
  const std::lock_guard lock(patterns_->mutex);
  auto& recent = patterns_->recent;
  recent.push_front(made);
  std::size_t bytes = 0, kept = 0;
  while (kept < recent.size() && kept < kCoronaPatternsKept && bytes + recent[kept]->bytes() <= kCoronaPatternBytesKept)
    bytes += recent[kept++]->bytes();
  recent.resize(std::max<std::size_t>(kept, 1));
  return made;
}

void CiliaryCorona::add(const CompactSource& source, ImageRGBA& glare_energy, int threads) const {
  const std::shared_ptr<const Pattern> values = pattern(source, glare_energy.width_px, glare_energy.height_px, threads);
  if (!values) return;
  const int columns = values->to_x - values->from_x + 1;
  parallel_chunks(values->to_y - values->from_y + 1, threads, [&](int first, int last) {
    for (int y = values->from_y + first; y < values->from_y + last; ++y)
      for (int x = values->from_x; x <= values->to_x; ++x) {
        const std::size_t at = static_cast<std::size_t>(y - values->from_y) * columns + (x - values->from_x);
        if (values->adds[at] == 0) continue;
        const double c = values->c[at];
        float* rgba = glare_energy.pixel(x, y);
        for (int channel = 0; channel < 3; ++channel)
          rgba[channel] += static_cast<float>(source.energy[static_cast<std::size_t>(channel)] * c);
      }
  });
}

}  // namespace glarelab
