#include "runner/timing/flip_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace glarelab {

Percentiles percentiles(std::vector<double> values_s) {
  Percentiles result;
  if (values_s.empty()) return result;
  std::sort(values_s.begin(), values_s.end());
  const auto rank = [&](double percent) {
    const auto n = static_cast<double>(values_s.size());
    const auto index = static_cast<std::size_t>(std::max(1.0, std::ceil(percent / 100.0 * n))) - 1;
    return values_s[std::min(index, values_s.size() - 1)];
  };
  result.p50_s = rank(50.0);
  result.p99_s = rank(99.0);
  result.max_s = values_s.back();
  return result;
}

FlipTimingFigures flip_timing_figures(const std::vector<double>& flip_s, double refresh_hz, long missed,
                                      const std::vector<double>& draw_s, const std::vector<double>& present_call_s,
                                      const std::vector<double>& loop_overhead_s) {
  FlipTimingFigures figures;
  figures.frames = static_cast<long>(flip_s.size());
  figures.nominal_period_s = 1.0 / refresh_hz;
  figures.missed_deadlines = missed;
  std::vector<double> intervals;
  for (std::size_t i = 1; i < flip_s.size(); ++i) intervals.push_back(flip_s[i] - flip_s[i - 1]);
  if (!intervals.empty()) {
    double sum = 0.0;
    for (double interval : intervals) sum += interval;
    figures.interval_mean_s = sum / static_cast<double>(intervals.size());
    double squares = 0.0;
    for (double interval : intervals) squares += (interval - figures.interval_mean_s) * (interval - figures.interval_mean_s);
    figures.interval_sd_s = intervals.size() > 1 ? std::sqrt(squares / static_cast<double>(intervals.size() - 1)) : 0.0;
    figures.interval_min_s = *std::min_element(intervals.begin(), intervals.end());
    figures.interval_max_s = *std::max_element(intervals.begin(), intervals.end());
  }
  figures.draw = percentiles(draw_s);
  figures.present_call = percentiles(present_call_s);
  figures.loop_overhead = percentiles(loop_overhead_s);
  return figures;
}

std::string FlipTimingFigures::describe() const {
  char text[1024];
  const auto ms = [](double s) { return 1000.0 * s; };
  std::snprintf(text, sizeof text,
                "%ld frames; flip interval mean %.6f ms (nominal %.6f ms, %+.6f ms), SD %.6f ms, min %.6f ms, max "
                "%.6f ms; missed deadlines %ld (interval > 1.5 periods); present call p50 %.4f ms, p99 %.4f ms, max "
                "%.4f ms; loop overhead p50 %.4f ms, p99 %.4f ms, max %.4f ms (goal p99 < 0.3 ms); drawing p50 %.4f "
                "ms, p99 %.4f ms",
                frames, ms(interval_mean_s), ms(nominal_period_s), ms(interval_mean_s - nominal_period_s),
                ms(interval_sd_s), ms(interval_min_s), ms(interval_max_s), missed_deadlines, ms(present_call.p50_s),
                ms(present_call.p99_s), ms(present_call.max_s), ms(loop_overhead.p50_s), ms(loop_overhead.p99_s),
                ms(loop_overhead.max_s), ms(draw.p50_s), ms(draw.p99_s));
  return text;
}

}  // namespace glarelab
