#include "protocols/comparison_luminance.h"

#include <cmath>
#include <stdexcept>
#include <algorithm>
#include <string>

#include "core/number_text.h"
#include "protocols/adaptive_procedure.h"

namespace glarelab {

TrialPlan with_comparison_luminance(TrialPlan plan, const std::vector<double>& luminance_cd_m2) {
  if (plan.comparison_positions.empty())
    throw std::invalid_argument("condition '" + plan.condition_name + "' (" + plan.procedure +
                                ") has no comparison to set: an intensity applies to staircase and QUEST "
                                "conditions, settings to adjustment conditions");
  if (luminance_cd_m2.size() != plan.comparison_positions.size())
    throw std::invalid_argument("condition '" + plan.condition_name + "' (" + plan.procedure + ") takes " +
                                std::to_string(plan.comparison_positions.size()) + " comparison luminance(s), found " +
                                std::to_string(luminance_cd_m2.size()) +
                                (plan.comparison_positions.size() == 1 ? " (give --intensity)" : " (give --settings L R)"));
  for (std::size_t i = 0; i < luminance_cd_m2.size(); ++i) {
    const double target_cd_m2 = luminance_cd_m2[i];
    if (!std::isfinite(target_cd_m2) || target_cd_m2 <= 0.0)
      throw std::invalid_argument("comparison luminance must be finite and > 0 cd/m2, found " +
                                  number_text(target_cd_m2));
    const auto position = static_cast<std::size_t>(plan.comparison_positions[i]);
    // The scene's scale is (peak it is shown at) / (its own peak): the same factor carries it to
    // the new peak.
    const double shown_cd_m2 = plan.source_luminance_cd_m2.at(position);
    plan.scene_scale.at(position) *= target_cd_m2 / shown_cd_m2;
    plan.source_luminance_cd_m2.at(position) = target_cd_m2;
  }
  if (!plan.adjustment_start_cd_m2.empty()) {
    plan.adjustment_start_cd_m2 = luminance_cd_m2;
    return plan;
  }
  // Adaptive: one comparison against one reference, as AdaptiveProcedure::next_trial scores it.
  const auto comparison = static_cast<std::size_t>(plan.comparison_positions[0]);
  const std::size_t reference = 1 - comparison;
  const double intensity_cd_m2 = luminance_cd_m2[0];
  const double reference_cd_m2 = plan.source_luminance_cd_m2.at(reference);
  plan.intensity = intensity_cd_m2;
  const std::vector<std::string>& responses = plan.allowed_responses;
  if (responses.size() >= 2) {
    if (std::abs(intensity_cd_m2 - reference_cd_m2) <= 1e-9 * std::max(intensity_cd_m2, reference_cd_m2))
      plan.correct_response = responses.size() == 3 ? responses[2] : responses[comparison];
    else
      plan.correct_response = responses[intensity_cd_m2 > reference_cd_m2 ? comparison : reference];
  }
  return plan;
}

}  // namespace glarelab

namespace glarelab {
namespace {

bool is_adaptive(const Experiment& experiment) {
  return experiment.procedure == "staircase" || experiment.procedure == "quest" ||
         experiment.procedure == "quest_plus" || experiment.procedure == "psi";
}

std::string quoted_list(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "'" : ", '") + name + "'";
  return text;
}

}  // namespace

void show_condition_in_preview(Procedure& procedure, const Experiment& experiment, const std::string& condition) {
  auto* adaptive = dynamic_cast<AdaptiveProcedure*>(&procedure);
  if (adaptive == nullptr) return;
  for (std::size_t row = 0; row < experiment.conditions.size(); ++row)
    if (experiment.conditions[row].name() == condition) {
      adaptive->show_row_on_its_tracks_next_trial(row);
      return;
    }
}

std::string preview_note(const Procedure& procedure) {
  const auto* adaptive = dynamic_cast<const AdaptiveProcedure*>(&procedure);
  return adaptive == nullptr ? std::string() : adaptive->preview_note();
}

std::string why_no_session_shows(const Experiment& experiment, const std::string& condition) {
  if (experiment.conditions.empty()) return "the experiment has no condition rows";
  if (is_adaptive(experiment)) {
    std::vector<std::string> shown;
    for (const AdaptiveTrackSpec& track : experiment.adaptive.tracks) {
      if (!track.quest_plus.conditions.empty()) {
        shown.insert(shown.end(), track.quest_plus.conditions.begin(), track.quest_plus.conditions.end());
      } else {
        shown.push_back(track.condition.empty() ? experiment.conditions.front().name() : track.condition);
      }
    }
    if (std::find(shown.begin(), shown.end(), condition) == shown.end())
      return "no track of the " + experiment.procedure + " procedure shows it (the tracks show " + quoted_list(shown) + ")";
    return "";
  }
  if (experiment.design.blocks.empty()) return "";
  std::vector<std::string> blocks;
  for (const BlockSpec& block : experiment.design.blocks) {
    blocks.push_back(block.name);
    if (block.conditions.empty() ||
        std::find(block.conditions.begin(), block.conditions.end(), condition) != block.conditions.end())
      return "";
  }
  return "it is in no block of [[blocks]] (" + quoted_list(blocks) + "), so no trial shows it";
}

}  // namespace glarelab
