#include "analysis/timing_figures.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "analysis/report_numbers.h"
#include "analysis/svg_plot.h"

namespace glarelab::analysis {
namespace {

// A histogram of finite values over [low, high] in `bins` bins (a value at high in the last bin).
std::vector<long> histogram(const std::vector<double>& values, double low, double high, int bins) {
  std::vector<long> counts(static_cast<std::size_t>(bins), 0);
  // Halved so that high - low stays finite for values near +-DBL_MAX.
  const double half_span = 0.5 * high - 0.5 * low;
  for (double v : values) {
    const double fraction = half_span > 0.0 ? (0.5 * v - 0.5 * low) / half_span : 0.0;
    const int bin = std::isfinite(fraction) ? static_cast<int>(std::clamp(fraction * bins, 0.0, bins - 1.0)) : 0;
    ++counts[static_cast<std::size_t>(bin)];
  }
  return counts;
}

// Bars of a histogram over [low, high].
void draw_histogram(SvgPlot& plot, const std::vector<long>& counts, double low, double high, const std::string& colour) {
  plot.set_x_range(low, high);
  plot.set_y_range(0.0, static_cast<double>(*std::max_element(counts.begin(), counts.end())) * 1.1);
  const double width = (high - low) / static_cast<double>(counts.size());
  for (std::size_t b = 0; b < counts.size(); ++b)
    plot.bar(low + (static_cast<double>(b) + 0.5) * width, width * 0.95, static_cast<double>(counts[b]), colour);
}

Figure response_time_figure(const TimingQuality& timing) {
  SvgPlot plot("Response times (all answered trials)", "response time (s)", "trials");
  // Only finite times are binned: a bin index from inf or NaN is undefined (the loader already
  // drops them; this keeps the figure safe for any caller).
  std::vector<double> values;
  for (double v : timing.response_times_s)
    if (std::isfinite(v)) values.push_back(v);
  const auto [min_it, max_it] = std::minmax_element(values.begin(), values.end());
  const double low = *min_it;
  const double high = *max_it > low ? *max_it : low + 1.0;
  draw_histogram(plot, histogram(values, low, high, 30), low, high, series_colour(1));
  return {"response_times", "timing", "Histogram of response times.", plot.svg()};
}

// The flip intervals of a timing test in ms: their histogram, with the mean interval (the
// measured refresh period) dashed.
Figure flip_histogram_figure(const SessionTiming& s, std::size_t index, double mean_ms) {
  std::vector<double> ms;
  for (double interval : s.flip_intervals_s) ms.push_back(1e3 * interval);
  const auto [min_it, max_it] = std::minmax_element(ms.begin(), ms.end());
  // A virtual clock gives every interval the same length (to rounding: flip times k / rate differ
  // in their last bits): a spread under 1 us gets a 2 ms window with the interval in the middle of
  // its 21st bin (of 40, 0.05 ms each), so one bar holds them all and is visible.
  const bool spread = *max_it - *min_it > 1e-3;
  const double centre = 0.5 * (*min_it + *max_it);
  const double low = spread ? *min_it : centre - 1.025;
  const double high = spread ? *max_it : centre + 0.975;
  SvgPlot plot("Flip intervals, timing test: " + s.label, "interval between consecutive flips (ms)", "flips");
  const std::vector<long> counts = histogram(ms, low, high, 40);
  draw_histogram(plot, counts, low, high, series_colour(0));
  const double top = static_cast<double>(*std::max_element(counts.begin(), counts.end())) * 1.1;
  plot.line({mean_ms, mean_ms}, {0.0, top}, "#d55e00", 1.5, true);
  plot.legend("mean " + fixed(mean_ms, 3) + " ms (dashed)", "#d55e00");
  plot.note(std::to_string(ms.size()) + " intervals, " + std::to_string(s.dropped) + " missed deadline(s); SD " +
            fixed(1e3 * s.frame_interval_sd_s.value_or(0.0), 3) + " ms");
  return {"flip_intervals_" + std::to_string(index), "timing",
          "Histogram of the intervals between consecutive flips of the timing test (" + s.label + ").", plot.svg()};
}

// The flip intervals in flip order; a flip that missed its deadline marked red. Beyond 1500
// intervals the line shows each run of flips by its lowest and highest interval (two lines), so
// no spike is lost to thinning.
Figure flip_series_figure(const SessionTiming& s, std::size_t index, double mean_ms) {
  constexpr std::size_t kMostPoints = 1500;
  const std::size_t n = s.flip_intervals_s.size();
  SvgPlot plot("Flip intervals in order, timing test: " + s.label, "flip", "interval before the flip (ms)", 640, 320);
  double low = mean_ms, high = mean_ms;
  for (double interval : s.flip_intervals_s) {
    low = std::min(low, 1e3 * interval);
    high = std::max(high, 1e3 * interval);
  }
  const double pad = std::max(0.08 * (high - low), 0.5);
  plot.set_x_range(0.0, static_cast<double>(n + 1));
  plot.set_y_range(std::max(0.0, low - pad), high + pad);
  const std::size_t run = (n + kMostPoints - 1) / kMostPoints;
  std::vector<double> x, lowest, highest, dropped_x, dropped_y;
  for (std::size_t start = 0; start < n; start += run) {
    double run_low = 1e3 * s.flip_intervals_s[start], run_high = run_low;
    for (std::size_t i = start; i < std::min(n, start + run); ++i) {
      run_low = std::min(run_low, 1e3 * s.flip_intervals_s[i]);
      run_high = std::max(run_high, 1e3 * s.flip_intervals_s[i]);
    }
    x.push_back(static_cast<double>(start + 1));
    lowest.push_back(run_low);
    highest.push_back(run_high);
  }
  for (std::size_t i = 0; i < n; ++i)
    if (s.interval_dropped[i]) {
      dropped_x.push_back(static_cast<double>(i + 1));
      dropped_y.push_back(1e3 * s.flip_intervals_s[i]);
    }
  plot.line({0.0, static_cast<double>(n + 1)}, {mean_ms, mean_ms}, "#888", 1.0, true);
  plot.line(x, highest, series_colour(0), 1.0);
  if (run > 1) {
    plot.line(x, lowest, series_colour(4), 1.0);
    plot.note("each point spans " + std::to_string(run) + " flips: their highest (dark) and lowest (light) interval");
  }
  plot.markers(dropped_x, dropped_y, "#d00", 3.5);
  plot.legend("interval before each flip", series_colour(0));
  plot.legend("mean " + fixed(mean_ms, 3) + " ms (dashed)", "#888");
  plot.legend(std::to_string(dropped_x.size()) + " missed deadline(s) (dots)", "#d00");
  return {"flip_series_" + std::to_string(index), "timing",
          "Intervals between consecutive flips of the timing test in flip order, missed deadlines marked (" + s.label +
              ").",
          plot.svg()};
}

}  // namespace

std::vector<Figure> timing_figures(const TimingQuality& timing) {
  std::vector<Figure> figures;
  if (std::any_of(timing.response_times_s.begin(), timing.response_times_s.end(), [](double v) { return std::isfinite(v); }))
    figures.push_back(response_time_figure(timing));
  std::size_t index = 0;
  for (const SessionTiming& s : timing.sessions) {
    if (!s.timing_test || s.flip_intervals_s.empty()) continue;
    const double mean_ms = 1e3 * s.frame_interval_mean_s.value_or(0.0);
    ++index;
    figures.push_back(flip_histogram_figure(s, index, mean_ms));
    figures.push_back(flip_series_figure(s, index, mean_ms));
  }
  return figures;
}

}  // namespace glarelab::analysis
