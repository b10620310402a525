#include "analysis/tracker_quality.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "analysis/statistics.h"

namespace glarelab::analysis {
namespace {

constexpr double kBlinkMin_s = 0.05;
constexpr double kBlinkMax_s = 0.5;
constexpr double kTraceStart_s = -0.5;
constexpr double kTraceEnd_s = 2.0;
constexpr double kTraceBin_s = 0.05;

long count_blinks(const std::vector<const TrackerSampleRecord*>& eye_samples) {
  long blinks = 0;
  bool in_gap = false;
  double gap_start_s = 0.0;
  double last_valid_s = 0.0;
  bool seen_valid = false;
  for (const TrackerSampleRecord* sample : eye_samples) {
    const bool valid = sample->valid && sample->pupil_diameter_mm.has_value();
    if (!valid) {
      if (!in_gap && seen_valid) {
        in_gap = true;
        gap_start_s = last_valid_s;
      }
      continue;
    }
    if (in_gap) {
      // Gap duration from the last valid sample before it to the first valid one after it.
      const double gap_s = sample->session_time_s - gap_start_s;
      if (gap_s >= kBlinkMin_s && gap_s <= kBlinkMax_s) ++blinks;
      in_gap = false;
    }
    seen_valid = true;
    last_valid_s = sample->session_time_s;
  }
  return blinks;
}

}  // namespace

TrackerQuality analyse_tracker(const LoadedData& data) {
  TrackerQuality quality;
  const auto bins = static_cast<std::size_t>(std::lround((kTraceEnd_s - kTraceStart_s) / kTraceBin_s));
  for (const LoadedSession& session : data.sessions) {
    if (session.tracker_samples.empty()) continue;
    SessionTracker tracker;
    tracker.label = session.label;
    std::map<int, std::vector<const TrackerSampleRecord*>> by_eye;
    for (const TrackerSampleRecord& sample : session.tracker_samples) {
      ++tracker.samples;
      tracker.valid += sample.valid ? 1 : 0;
      by_eye[sample.eye].push_back(&sample);
    }
    for (const auto& entry : by_eye) tracker.blinks += count_blinks(entry.second);

    std::vector<double> sum(bins, 0.0);
    std::vector<long> count(bins, 0);
    const auto& samples = session.tracker_samples;  // sorted by session_time_s
    for (const LoadedTrial& trial : session.trials) {
      const double onset_s = trial.record.onset_s;
      auto it = std::lower_bound(samples.begin(), samples.end(), onset_s + kTraceStart_s,
                                 [](const TrackerSampleRecord& s, double t) { return s.session_time_s < t; });
      for (; it != samples.end() && it->session_time_s < onset_s + kTraceEnd_s; ++it) {
        if (!it->valid || !it->pupil_diameter_mm) continue;
        const auto bin = static_cast<std::size_t>((it->session_time_s - onset_s - kTraceStart_s) / kTraceBin_s);
        if (bin >= bins) continue;
        sum[bin] += *it->pupil_diameter_mm;
        ++count[bin];
      }
    }
    for (std::size_t b = 0; b < bins; ++b) {
      tracker.pupil.time_from_onset_s.push_back(kTraceStart_s + (static_cast<double>(b) + 0.5) * kTraceBin_s);
      tracker.pupil.pupil_diameter_mm.push_back(count[b] > 0 ? std::optional<double>(sum[b] / static_cast<double>(count[b]))
                                                             : std::nullopt);
    }
    std::vector<double> ages_ms;
    for (const LoadedTrial& trial : session.trials)
      for (const FrameRecord& frame : trial.frames)
        if (frame.gaze_age_s) ages_ms.push_back(1000.0 * *frame.gaze_age_s);
    if (!ages_ms.empty()) {
      std::sort(ages_ms.begin(), ages_ms.end());
      GazeLatency latency;
      latency.frames = static_cast<long>(ages_ms.size());
      latency.median_ms = median(ages_ms);
      // Nearest rank: the smallest value with at least 95 % of the frames at or below it.
      const auto rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(ages_ms.size())));
      latency.p95_ms = ages_ms[std::max<std::size_t>(rank, 1) - 1];
      latency.max_ms = ages_ms.back();
      tracker.gaze_latency = latency;
    }
    quality.sessions.push_back(std::move(tracker));
  }
  return quality;
}

}  // namespace glarelab::analysis
