#include "glare/analytic/spencer_flare_lines.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/parallel_for.h"
#include "core/random.h"

namespace glarelab {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRadPerDeg = kPi / 180.0;

// Visits, in order of azimuth, each of the lines (sorted by azimuth) whose azimuth lies within
// `span_rad` after `start_rad` (in [0, 2 pi)), the search wrapping at 2 pi: the lines that can
// reach one azimuth, where a sum over all of them would add zeros.
template <typename Lines, typename Visit>
void for_lines_within(const Lines& lines, double start_rad, double span_rad, Visit visit) {
  const auto first = std::lower_bound(lines.begin(), lines.end(), start_rad,
                                      [](const auto& line, double a) { return line.azimuth_rad < a; });
  std::size_t index = static_cast<std::size_t>(first - lines.begin());
  for (std::size_t step = 0; step < lines.size(); ++step, ++index) {
    const auto& line = lines[index % lines.size()];
    double ahead = line.azimuth_rad - start_rad;
    if (ahead < 0.0) ahead += 2.0 * kPi;
    if (ahead > span_rad) break;
    visit(line);
  }
}

// A convex polygon of at most 8 vertices (a square clipped by two half-planes has at most 6).
struct Polygon {
  std::array<double, 16> xy{};
  int n = 0;
  void add(double x, double y) {
    xy[2 * n] = x;
    xy[2 * n + 1] = y;
    ++n;
  }
};

// Sutherland-Hodgman against the half-plane s * cross(u, p) >= 0 (s = +1: counter-clockwise of the
// direction u, s = -1: clockwise of it), u = (ux, uy) through the origin.
Polygon clip(const Polygon& in, double ux, double uy, double s) {
  Polygon out;
  for (int i = 0; i < in.n; ++i) {
    const int j = (i + 1) % in.n;
    const double ax = in.xy[2 * i], ay = in.xy[2 * i + 1], bx = in.xy[2 * j], by = in.xy[2 * j + 1];
    const double da = s * (ux * ay - uy * ax), db = s * (ux * by - uy * bx);
    if (da >= 0.0) out.add(ax, ay);
    if ((da >= 0.0) != (db >= 0.0)) {
      const double t = da / (da - db);
      out.add(ax + t * (bx - ax), ay + t * (by - ay));
    }
  }
  return out;
}

double area(const Polygon& polygon) {
  double twice = 0.0;
  for (int i = 0; i < polygon.n; ++i) {
    const int j = (i + 1) % polygon.n;
    twice += polygon.xy[2 * i] * polygon.xy[2 * j + 1] - polygon.xy[2 * j] * polygon.xy[2 * i + 1];
  }
  return 0.5 * std::abs(twice);
}

// The area of the unit square centred at (cx, cy) between the directions `from` and `to`
// (counter-clockwise, to - from <= pi) about the origin.
double wedge_area(double cx, double cy, double from, double to) {
  Polygon square;
  square.add(cx - 0.5, cy - 0.5);
  square.add(cx + 0.5, cy - 0.5);
  square.add(cx + 0.5, cy + 0.5);
  square.add(cx - 0.5, cy + 0.5);
  const Polygon first = clip(square, std::cos(from), std::sin(from), 1.0);
  if (first.n < 3) return 0.0;
  const Polygon both = clip(first, std::cos(to), std::sin(to), -1.0);
  return both.n < 3 ? 0.0 : area(both);
}

// The fraction of the unit pixel at (cx, cy) inside the wedge phi +- h.
double pixel_fraction(double cx, double cy, double phi, double h) {
  if (h >= kPi) return 1.0;
  if (2.0 * h <= kPi) return wedge_area(cx, cy, phi - h, phi + h);
  // Wider than a half-plane: the square less the narrower wedge that is left out.
  return 1.0 - wedge_area(cx, cy, phi + h, phi - h + 2.0 * kPi);
}

// The chord-length profile of a uniform disc seen from afar, a semicircle density on [-b, b]: its
// cumulative distribution (b = 0: a step at 0).
double semicircle_cdf(double x, double b) {
  if (b <= 0.0) return x > 0.0 ? 1.0 : x < 0.0 ? 0.0 : 0.5;
  if (x <= -b) return 0.0;
  if (x >= b) return 1.0;
  return 0.5 + (x * std::sqrt(b * b - x * x) + b * b * std::asin(x / b)) / (kPi * b * b);
}

// One line's box of half width h convolved with the semicircle of half width b, at azimuth offset y.
double blurred_box(double y, double h, double b) { return semicircle_cdf(y + h, b) - semicircle_cdf(y - h, b); }

}  // namespace

FlareLines::FlareLines(FlareLineSet set, std::uint64_t seed) : set_(set) {
  const CounterRandom random(seed, RandomStream::spencer_flare_lines);
  const std::uint32_t sub = 2u * static_cast<std::uint32_t>(set);
  lines_.resize(kFlareLineCount);
  for (int k = 0; k < kFlareLineCount; ++k) {
    lines_[k].azimuth_rad = 2.0 * kPi * random.uniform(static_cast<std::uint64_t>(k), sub);
    lines_[k].intensity = random.uniform(static_cast<std::uint64_t>(k), sub + 1u);
    intensity_sum_ += lines_[k].intensity;
  }
  std::sort(lines_.begin(), lines_.end(), [](const FlareLine& a, const FlareLine& b) { return a.azimuth_rad < b.azimuth_rad; });
}

double FlareLines::half_width_rad(double angle_deg) {
  const double s = std::sin(angle_deg * kRadPerDeg);
  const double h = 0.5 * kFlareLineWidthDeg * kRadPerDeg / std::max(s, 1e-300);
  return std::min(h, kPi);
}

double FlareLines::pixel_coverage(int dx, int dy, const DisplayGeometry& geometry) const {
  const double r_px = std::hypot(static_cast<double>(dx), static_cast<double>(dy));
  const double angle_deg = std::atan2(r_px * geometry.pixel_pitch_mm, geometry.viewing_distance_mm) / kRadPerDeg;
  const double h = half_width_rad(angle_deg);
  const double cx = dx, cy = dy;
  double sum = 0.0;
  // Only the lines whose wedge can reach the pixel: its azimuths lie within asin(sqrt(1/2) / r) of
  // its centre's (the square's half diagonal seen from the source).
  const double reach = r_px > 0.7072 ? std::asin(std::min(1.0, 0.70711 / r_px)) + h + 1e-9 : 2.0 * kPi;
  if (reach >= kPi) {
    for (const FlareLine& line : lines_) sum += line.intensity * pixel_fraction(cx, cy, line.azimuth_rad, h);
    return sum;
  }
  double start = std::atan2(cy, cx) - reach;
  if (start < 0.0) start += 2.0 * kPi;
  for_lines_within(lines_, start, 2.0 * reach,
                   [&](const auto& line) { sum += line.intensity * pixel_fraction(cx, cy, line.azimuth_rad, h); });
  return sum;
}

double FlareLines::normalised(double angle_deg, double azimuth_rad, double source_diameter_deg) const {
  const double h = half_width_rad(angle_deg);
  if (h >= kPi || intensity_sum_ <= 0.0) return 1.0;
  double b = 0.0;
  if (source_diameter_deg > 0.0) {
    const double ratio = std::sin(0.5 * source_diameter_deg * kRadPerDeg) / std::sin(angle_deg * kRadPerDeg);
    if (ratio >= 1.0) return 1.0;  // inside the source: every direction's lines pass here
    b = std::asin(ratio);
  }
  const double reach = h + b;
  const bool wraps = reach > kPi;
  double sum = 0.0;
  if (wraps) {
    for (const FlareLine& line : lines_) {
      const double y = std::remainder(azimuth_rad - line.azimuth_rad, 2.0 * kPi);
      sum += line.intensity * (blurred_box(y, h, b) + blurred_box(y - 2.0 * kPi, h, b) + blurred_box(y + 2.0 * kPi, h, b));
    }
  } else {
    // A blurred box is exactly 0 farther than h + b from its line: only the lines within that reach
    // of the azimuth (sorted by azimuth; the search wraps at 2 pi) are summed.
    double start = std::fmod(azimuth_rad - reach, 2.0 * kPi);
    if (start < 0.0) start += 2.0 * kPi;
    for_lines_within(lines_, start, 2.0 * reach, [&](const auto& line) {
      sum += line.intensity * blurred_box(std::remainder(azimuth_rad - line.azimuth_rad, 2.0 * kPi), h, b);
    });
  }
  // Each blurred box holds 2h of azimuth, so the ring's mean is intensity_sum 2h / (2 pi).
  return sum / (intensity_sum_ * h / kPi);
}

std::optional<FlareLineSet> flare_line_set_of_component(int component) {
  if (component == 1 || component == 2) return FlareLineSet::corona;
  if (component == 3) return FlareLineSet::halo;
  if (component == 0) return std::nullopt;
  throw std::invalid_argument("glare/analytic/spencer_flare_lines: Spencer's components are 0-3, got " + std::to_string(component));
}

void apply_flare_lines(DisplayKernel& kernel, const FlareLines& lines, const DisplayGeometry& geometry, int threads) {
  const int w = kernel.width_px(), hgt = kernel.height_px();
  const std::size_t n = static_cast<std::size_t>(w) * hgt;
  std::vector<double> coverage(n, 0.0);
  std::vector<int> ring(n, 0);
  parallel_chunks(hgt, threads, [&](int first, int last) {
    for (int row = first; row < last; ++row)
      for (int col = 0; col < w; ++col) {
        const int dx = col - kernel.half_width_px, dy = row - kernel.half_height_px;
        const std::size_t at = static_cast<std::size_t>(row) * w + col;
        coverage[at] = lines.pixel_coverage(dx, dy, geometry);
        ring[at] = static_cast<int>(std::lround(std::hypot(static_cast<double>(dx), static_cast<double>(dy))));
      }
  });
  const int rings = static_cast<int>(std::lround(std::hypot(kernel.half_width_px, kernel.half_height_px))) + 1;
  for (int c = 0; c < kernel.channels; ++c) {
    double* values = kernel.values.data() + static_cast<std::size_t>(c) * n;
    // Each ring's smooth energy and its energy under the lines: their ratio scales the ring back.
    std::vector<double> smooth(static_cast<std::size_t>(rings), 0.0), lined(static_cast<std::size_t>(rings), 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      smooth[static_cast<std::size_t>(ring[i])] += values[i];
      lined[static_cast<std::size_t>(ring[i])] += values[i] * coverage[i];
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t k = static_cast<std::size_t>(ring[i]);
      if (lined[k] > 0.0) values[i] *= coverage[i] * (smooth[k] / lined[k]);
    }
  }
}

DisplayKernel spencer_flare_kernel(const spencer::Mixture& mixture, const DisplayGeometry& geometry, int half_width_px,
                                   int half_height_px, std::uint64_t seed, int threads) {
  const std::array<double, 4> weights{mixture.f0, mixture.f1, mixture.f2, mixture.f3};
  DisplayKernel sum;
  sum.half_width_px = half_width_px;
  sum.half_height_px = half_height_px;
  sum.channels = mixture.f3 > 0.0 ? 3 : 1;
  const std::size_t n = static_cast<std::size_t>(sum.width_px()) * sum.height_px();
  sum.values.assign(static_cast<std::size_t>(sum.channels) * n, 0.0);
  for (int i = 0; i < 4; ++i) {
    if (weights[i] == 0.0) continue;
    spencer::Mixture unit;
    (i == 0 ? unit.f0 : i == 1 ? unit.f1 : i == 2 ? unit.f2 : unit.f3) = 1.0;
    DisplayKernel component = analytic_display_kernel(AnalyticPsf::spencer(unit), geometry, half_width_px, half_height_px, threads);
    if (const std::optional<FlareLineSet> set = flare_line_set_of_component(i))
      apply_flare_lines(component, FlareLines(*set, seed), geometry, threads);
    for (int c = 0; c < sum.channels; ++c) {
      const std::size_t from = static_cast<std::size_t>(component.channels == 3 ? c : 0) * n;
      for (std::size_t j = 0; j < n; ++j) sum.values[c * n + j] += weights[i] * component.values[from + j];
    }
  }
  return sum;
}

Psf spencer_flare_psf_image(const spencer::Mixture& mixture, double degrees_per_pixel, int size_px, std::uint64_t seed,
                            int threads) {
  if (size_px % 2 != 0 || size_px < 2)
    throw std::invalid_argument("glare/analytic/spencer_flare_lines: a PSF image needs an even side, got " + std::to_string(size_px));
  // The flat display of glare/analytic/display_psf_image.h: only pitch / distance matters.
  const DisplayGeometry geometry{1000.0, 1000.0 * std::tan(degrees_per_pixel * kRadPerDeg)};
  const int half = size_px / 2;
  const DisplayKernel kernel = spencer_flare_kernel(mixture, geometry, half, half, seed, threads);
  Psf image;
  image.size_px = size_px;
  image.degrees_per_pixel = degrees_per_pixel;
  image.channels = kernel.channels;
  image.values.assign(static_cast<std::size_t>(image.channels) * size_px * size_px, 0.0);
  const std::size_t count = static_cast<std::size_t>(size_px) * size_px;
  for (int c = 0; c < image.channels; ++c) {
    double total = 0.0;
    for (int y = 0; y < size_px; ++y)
      for (int x = 0; x < size_px; ++x) total += image.at(c, x, y) = kernel.at(c, x - half, y - half);
    for (std::size_t k = 0; k < count; ++k) image.values[c * count + k] /= total;
  }
  return image;
}

}  // namespace glarelab
