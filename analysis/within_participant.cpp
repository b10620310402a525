#include "analysis/within_participant.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include <boost/math/distributions/students_t.hpp>

#include "core/parallel_for.h"

namespace glarelab::analysis {
namespace {

// 2 / 2^n, the exact signed-rank test's smallest two-sided p with n untied nonzero differences.
std::string smallest_p_text(std::size_t n) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", std::min(1.0, 2.0 / std::pow(2.0, static_cast<double>(n))));
  return text;
}

WithinParticipantEffect combine(const std::string& group, const std::vector<const ParticipantCell*>& cells) {
  WithinParticipantEffect effect;
  effect.group = group;
  std::vector<double> pse, baseline_pse;
  for (const ParticipantCell* cell : cells) {
    effect.participants.push_back(cell->participant);
    effect.shifts.push_back(*cell->shift);
    pse.push_back(cell->fit->pse);
    baseline_pse.push_back(cell->fit->pse - *cell->shift);
  }
  const std::size_t n = effect.shifts.size();
  if (n > 0) {
    double sum = 0.0;
    for (double s : effect.shifts) sum += s;
    effect.mean_shift = sum / static_cast<double>(n);
  }
  if (n < 2) {
    effect.paired_t.unavailable = std::to_string(n) + " participant" + (n == 1 ? "" : "s") +
                                  " with a PSE at both levels: a paired t test needs at least 2";
  } else {
    effect.paired_t = paired_t_test(pse, baseline_pse);
    if (effect.paired_t.ok()) {
      const double sd = standard_deviation(effect.shifts);
      const double t = boost::math::quantile(boost::math::students_t_distribution<double>(static_cast<double>(n - 1)), 0.975);
      const double half = t * sd / std::sqrt(static_cast<double>(n));
      effect.interval = Interval{effect.mean_shift - half, effect.mean_shift + half};
    }
  }
  if (n < kWilcoxonMinimumParticipants) {
    effect.wilcoxon.unavailable =
        std::to_string(n) + " participant" + (n == 1 ? "" : "s") + ": the exact signed-rank test's smallest two-sided p is 2/2^" +
        std::to_string(n) + " = " + smallest_p_text(n) +
        ", so it is run from " + std::to_string(kWilcoxonMinimumParticipants) + " participants";
  } else {
    effect.wilcoxon = wilcoxon_signed_rank(pse, baseline_pse);
  }
  return effect;
}

}  // namespace

long ParticipantCell::answers() const {
  long n = 0;
  for (const StimulusLevel& level : levels) n += level.trials;
  return n;
}

WithinParticipantAnalysis analyse_within_participants(std::vector<ParticipantCell> cells,
                                                      const std::vector<std::string>& group_order,
                                                      const std::string& baseline, unsigned threads) {
  WithinParticipantAnalysis analysis;
  analysis.baseline = baseline;
  for (const ParticipantCell& cell : cells)
    if (std::find(analysis.participants.begin(), analysis.participants.end(), cell.participant) == analysis.participants.end())
      analysis.participants.push_back(cell.participant);
  const auto rank = [&](const ParticipantCell& cell) {
    const auto p = std::find(analysis.participants.begin(), analysis.participants.end(), cell.participant);
    const auto g = std::find(group_order.begin(), group_order.end(), cell.group);
    return std::pair(p - analysis.participants.begin(), g - group_order.begin());
  };
  std::stable_sort(cells.begin(), cells.end(), [&](const ParticipantCell& a, const ParticipantCell& b) { return rank(a) < rank(b); });
  parallel_for(cells.size(), threads, [&](std::size_t c) { cells[c].fit = psignifit_pse(cells[c].levels); });

  std::map<std::string, int> groups_of;
  std::map<std::string, const ParticipantCell*> baseline_of;
  for (const ParticipantCell& cell : cells) {
    ++groups_of[cell.participant];
    if (cell.group == baseline && cell.fit) baseline_of[cell.participant] = &cell;
  }
  for (const auto& [participant, count] : groups_of) analysis.within = analysis.within || count >= 2;
  parallel_for(cells.size(), threads, [&](std::size_t c) {
    ParticipantCell& cell = cells[c];
    const auto base = baseline_of.find(cell.participant);
    if (cell.group == baseline || !cell.fit || base == baseline_of.end()) return;
    cell.shift = cell.fit->pse - base->second->fit->pse;
    cell.shift_interval = psignifit_pse_difference_interval(*base->second->fit, *cell.fit);
  });
  analysis.cells = std::move(cells);
  if (!analysis.within) return analysis;
  for (const std::string& group : group_order) {
    if (group == baseline) continue;
    std::vector<const ParticipantCell*> paired;
    for (const ParticipantCell& cell : analysis.cells)
      if (cell.group == group && cell.shift) paired.push_back(&cell);
    analysis.effects.push_back(combine(group, paired));
  }
  return analysis;
}

}  // namespace glarelab::analysis
