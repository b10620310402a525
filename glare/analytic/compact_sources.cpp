#include "glare/analytic/compact_sources.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace glarelab {
namespace {

double rec709_luminance(const float* rgba) { return 0.2126 * rgba[0] + 0.7152 * rgba[1] + 0.0722 * rgba[2]; }

// The median luminance, from every pixel of a small frame and every 4th pixel of every 4th row of a
// large one (the background of a frame is wide: a sparse sample finds it).
double median_luminance(const ImageRGBA& frame) {
  const int step = static_cast<long long>(frame.width_px) * frame.height_px > (1LL << 18) ? 4 : 1;
  std::vector<double> sample;
  for (int y = 0; y < frame.height_px; y += step)
    for (int x = 0; x < frame.width_px; x += step) sample.push_back(rec709_luminance(frame.pixel(x, y)));
  if (sample.empty()) return 0.0;
  const auto middle = sample.begin() + static_cast<std::ptrdiff_t>(sample.size() / 2);
  std::nth_element(sample.begin(), middle, sample.end());
  return *middle;
}

}  // namespace

double CompactSource::disc_diameter_px() const { return std::sqrt(8.0 * second_moment_px2); }

std::vector<CompactSource> compact_sources(const ImageRGBA& luminance, const ImageRGBA& energy, const CompactSourceRule& rule) {
  const int w = luminance.width_px, h = luminance.height_px;
  double peak = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) peak = std::max(peak, rec709_luminance(luminance.pixel(x, y)));
  const double threshold = std::max(rule.over_median * median_luminance(luminance), rule.of_peak * peak);
  std::vector<CompactSource> sources;
  if (!(threshold > 0.0)) return sources;
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(w) * h, 0);
  std::vector<std::pair<int, int>> stack, group;
  for (int y0 = 0; y0 < h; ++y0)
    for (int x0 = 0; x0 < w; ++x0) {
      const std::size_t at0 = static_cast<std::size_t>(y0) * w + x0;
      if (seen[at0] || rec709_luminance(luminance.pixel(x0, y0)) < threshold) continue;
      // The 8-connected group of pixels at or above the threshold.
      seen[at0] = 1;
      stack.assign(1, {x0, y0});
      group.clear();
      while (!stack.empty()) {
        const auto [x, y] = stack.back();
        stack.pop_back();
        group.emplace_back(x, y);
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
            const std::size_t at = static_cast<std::size_t>(ny) * w + nx;
            if (seen[at] || rec709_luminance(luminance.pixel(nx, ny)) < threshold) continue;
            seen[at] = 1;
            stack.emplace_back(nx, ny);
          }
      }
      // Its energy, centroid and second moment, weighted by the energy's luminance.
      CompactSource source;
      source.pixels = static_cast<int>(group.size());
      double weight = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0;
      for (const auto& [x, y] : group) {
        const float* e = energy.pixel(x, y);
        for (int c = 0; c < 3; ++c) source.energy[static_cast<std::size_t>(c)] += e[c];
        const double y_e = rec709_luminance(e);
        weight += y_e;
        sx += y_e * x;
        sy += y_e * y;
        sxx += y_e * (static_cast<double>(x) * x + static_cast<double>(y) * y);
      }
      if (!(weight > 0.0)) continue;
      source.x_px = sx / weight;
      source.y_px = sy / weight;
      source.second_moment_px2 =
          std::max(0.0, sxx / weight - source.x_px * source.x_px - source.y_px * source.y_px) + 1.0 / 6.0;
      if (source.disc_diameter_px() > rule.largest_diameter_px) continue;
      sources.push_back(source);
    }
  const auto luminance_of = [](const CompactSource& s) { return 0.2126 * s.energy[0] + 0.7152 * s.energy[1] + 0.0722 * s.energy[2]; };
  std::stable_sort(sources.begin(), sources.end(),
                   [&](const CompactSource& a, const CompactSource& b) { return luminance_of(a) > luminance_of(b); });
  if (sources.size() > static_cast<std::size_t>(std::max(0, rule.most))) sources.resize(static_cast<std::size_t>(std::max(0, rule.most)));
  return sources;
}

}  // namespace glarelab
