#include "analysis/pse_analysis.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <tuple>

#include <boost/math/distributions/students_t.hpp>

#include "core/parallel_for.h"

namespace glarelab::analysis {
namespace {

std::optional<double> number_of(const LoadedTrial& trial, const std::string& key) {
  const std::string* text = trial.condition_value(key);
  if (text == nullptr) return std::nullopt;
  double value = 0.0;
  const char* end = text->data() + text->size();
  const auto [ptr, ec] = std::from_chars(text->data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

// The glare gain the reference was shown with, as the procedure recorded it (its row's glare_gain,
// 1 without the column, 0 when its glare is control); the row's column for records without it.
double glare_gain_of(const LoadedTrial& trial) {
  if (const std::optional<double> recorded = number_of(trial, "reference_glare_gain")) return *recorded;
  return number_of(trial, "glare_gain").value_or(1.0);
}

}  // namespace

bool is_pse_trial(const LoadedTrial& trial) {
  const std::string* rule = trial.condition_value("response_rule");
  return trial.record.procedure == "staircase" && rule != nullptr && *rule == "pse";
}

PseAnalysis analyse_pse(const LoadedData& data, const PseOptions& options) {
  PseAnalysis analysis;
  struct Answer {
    double fraction;
    int kind;  // 1 comparison brighter, 0 reference brighter, -1 neither
    bool reversal;
  };
  std::vector<std::vector<Answer>> answers;
  for (const LoadedSession& session : data.sessions) {
    std::map<std::string, std::size_t> index_of;
    for (const LoadedTrial& trial : session.trials) {
      if (!is_pse_trial(trial)) continue;
      const TrialRecord& r = trial.record;
      const std::optional<double> peak = number_of(trial, "display_peak_cd_m2");
      const std::optional<double> reference = number_of(trial, "reference_cd_m2");
      if (!peak || !(*peak > 0.0) || !reference) continue;
      auto [found, inserted] = index_of.try_emplace(r.staircase, analysis.tracks.size());
      if (inserted) {
        PseTrack track;
        track.participant_label = session.label;
        track.name = r.staircase;
        if (const std::string* block = trial.condition_value("block_name")) track.group = *block;
        track.glare_gain = glare_gain_of(trial);
        track.reference_fraction = *reference / *peak;
        analysis.tracks.push_back(std::move(track));
        answers.emplace_back();
      }
      const std::string* comparison = trial.condition_value("comparison_response");
      const std::string* other = trial.condition_value("reference_response");
      if (!r.intensity || comparison == nullptr || other == nullptr) continue;
      int kind = -1;
      if (r.response == *comparison) kind = 1;
      else if (r.response == *other) kind = 0;
      else if (r.response == "abort" || r.response == "timeout") continue;  // no answer
      answers[found->second].push_back({*r.intensity / *peak, kind, r.reversal.value_or(0) == 1});
    }
  }

  std::vector<std::vector<StimulusLevel>> levels(analysis.tracks.size());
  for (std::size_t t = 0; t < analysis.tracks.size(); ++t) {
    PseTrack& track = analysis.tracks[t];
    std::vector<std::pair<double, bool>> named;
    std::vector<double> reversals;
    for (const Answer& a : answers[t]) {
      ++track.trials;
      if (a.kind < 0) ++track.neither;
      else named.emplace_back(a.fraction, a.kind == 1);
      if (a.reversal) reversals.push_back(a.fraction);
    }
    if (!reversals.empty()) {
      const int k = std::min<int>(options.last_reversals, static_cast<int>(reversals.size()));
      double sum = 0.0;
      for (std::size_t j = reversals.size() - static_cast<std::size_t>(k); j < reversals.size(); ++j) sum += reversals[j];
      track.reversal_mean_fraction = sum / k;
      track.reversals_used = k;
    }
    levels[t] = levels_from_trials(named);
  }
  std::vector<std::optional<PsignifitPse>> fits(analysis.tracks.size());
  parallel_for(analysis.tracks.size(), options.threads, [&](std::size_t t) { fits[t] = psignifit_pse(levels[t]); });
  for (std::size_t t = 0; t < analysis.tracks.size(); ++t) {
    PseTrack& track = analysis.tracks[t];
    track.fit = std::move(fits[t]);
    if (track.fit) {
      track.pse_fraction = track.fit->pse;
      track.pse_interval = track.fit->credible;
    } else {
      track.note = levels[t].empty() ? "no answer naming a side" : "no fit (one comparison level answered)";
      if (track.reversal_mean_fraction) {
        track.pse_fraction = track.reversal_mean_fraction;
        track.pse_from_reversals = true;
        track.note += ": PSE from the reversal mean";
      }
    }
  }
  // Tables read by participant, group and glare strength.
  std::stable_sort(analysis.tracks.begin(), analysis.tracks.end(), [](const PseTrack& a, const PseTrack& b) {
    return std::tie(a.participant_label, a.group, a.glare_gain) < std::tie(b.participant_label, b.group, b.glare_gain);
  });

  // The figure's points: per group and gain, the mean over participants.
  std::map<std::pair<std::string, double>, std::vector<const PseTrack*>> by_point;
  for (const PseTrack& track : analysis.tracks)
    if (track.pse_fraction) by_point[{track.group, track.glare_gain}].push_back(&track);
  for (const auto& [key, tracks] : by_point) {
    PsePoint point;
    point.group = key.first;
    point.glare_gain = key.second;
    point.participants = static_cast<int>(tracks.size());
    double sum = 0.0;
    for (const PseTrack* track : tracks) sum += *track->pse_fraction;
    point.mean_pse_fraction = sum / point.participants;
    if (point.participants == 1) {
      point.interval = tracks.front()->pse_interval;
    } else {
      double squares = 0.0;
      for (const PseTrack* track : tracks) squares += std::pow(*track->pse_fraction - point.mean_pse_fraction, 2);
      const double se = std::sqrt(squares / (point.participants - 1) / point.participants);
      const double t = boost::math::quantile(boost::math::students_t_distribution<double>(point.participants - 1), 0.975);
      point.interval = Interval{point.mean_pse_fraction - t * se, point.mean_pse_fraction + t * se};
    }
    analysis.points.push_back(point);
  }
  if (!analysis.tracks.empty()) {
    const double first = analysis.tracks.front().reference_fraction;
    const bool same = std::all_of(analysis.tracks.begin(), analysis.tracks.end(), [&](const PseTrack& t) {
      return std::abs(t.reference_fraction - first) <= 1e-9;
    });
    if (same) analysis.reference_fraction = first;
  }
  return analysis;
}

}  // namespace glarelab::analysis
