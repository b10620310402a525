#include "protocols/adaptive_procedure.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "protocols/forced_choice.h"
#include "protocols/json_text.h"
#include "core/random.h"

namespace glarelab {
namespace {

std::size_t row_named(const Experiment& experiment, const std::string& name) {
  if (experiment.conditions.empty()) throw std::invalid_argument("adaptive procedure: no condition rows");
  if (name.empty()) return 0;
  for (std::size_t row = 0; row < experiment.conditions.size(); ++row)
    if (experiment.conditions[row].name() == name) return row;
  throw std::invalid_argument("adaptive procedure: no condition row named '" + name + "'");
}

double peak_of(const std::map<std::string, double>& peaks, const std::string& scene) {
  const auto found = peaks.find(scene);
  if (found == peaks.end() || !(found->second > 0.0))
    throw std::invalid_argument("adaptive procedure: scene '" + scene + "' has no positive peak luminance to scale");
  return found->second;
}

}  // namespace

double AdaptiveProcedure::Track::next_luminance_cd_m2() const {
  // QUEST's scale is log10 cd/m2 (Watson & Pelli 1983 work on log intensity).
  return staircase ? staircase->next_intensity() : std::pow(10.0, quest->next_intensity());
}

AdaptiveProcedure::AdaptiveProcedure(const Experiment& experiment, const std::map<std::string, double>& source_peak_cd_m2)
    : experiment_(experiment), peak_cd_m2_(source_peak_cd_m2) {
  if (experiment.adaptive.tracks.empty()) throw std::invalid_argument("adaptive procedure: no staircase");
  for (const AdaptiveTrackSpec& spec : experiment.adaptive.tracks) {
    Track track;
    track.row = row_named(experiment, spec.condition);
    const ConditionRow& row = experiment.conditions[track.row];
    if (experiment.procedure == "staircase") {
      track.name = spec.staircase.name;
      track.staircase.emplace(spec.staircase);
    } else {
      track.name = spec.quest.name;
      track.quest.emplace(spec.quest);
    }
    for (const char* column : {"reference", "comparison"}) {
      const std::string* scene = row.find(column);
      if (scene == nullptr)
        throw std::invalid_argument("adaptive procedure: condition '" + row.name() + "' lacks " + column);
      peak_of(peak_cd_m2_, *scene);
    }
    tracks_.push_back(std::move(track));
  }
}

bool AdaptiveProcedure::finished() const {
  return std::all_of(tracks_.begin(), tracks_.end(), [](const Track& t) { return t.finished(); });
}

int AdaptiveProcedure::planned_trials() const {
  int total = 0;
  for (const Track& t : tracks_) total += t.staircase ? t.staircase->spec().n_trials : t.quest->spec().n_trials;
  return total;
}

const Staircase* AdaptiveProcedure::staircase(std::size_t track) const {
  return tracks_.at(track).staircase ? &*tracks_.at(track).staircase : nullptr;
}
const Quest* AdaptiveProcedure::quest(std::size_t track) const {
  return tracks_.at(track).quest ? &*tracks_.at(track).quest : nullptr;
}

// The same pass scheme as InterleavedStaircases::next (MultiStairHandler._startNewPass).
std::size_t AdaptiveProcedure::choose_track() {
  while (!finished()) {
    if (pass_remaining_.empty()) {
      for (std::size_t i = 0; i < tracks_.size(); ++i) pass_remaining_.push_back(i);
      shuffle_in_place(pass_remaining_, CounterRandom(experiment_.seed, RandomStream::staircase),
                       pass_ * tracks_.size());
      ++pass_;
    }
    const std::size_t candidate = pass_remaining_.front();
    pass_remaining_.erase(pass_remaining_.begin());
    if (!tracks_[candidate].finished()) return candidate;
  }
  throw std::logic_error("adaptive procedure: all staircases are finished");
}

TrialPlan AdaptiveProcedure::next_trial() {
  if (!current_) current_ = choose_track();
  const Track& track = tracks_[*current_];
  const ConditionRow& row = experiment_.conditions[track.row];
  const std::string& reference = *row.find("reference");
  const std::string& comparison = *row.find("comparison");
  const double intensity_cd_m2 = track.next_luminance_cd_m2();
  const ForcedChoiceSpec& spec = experiment_.forced_choice;
  const std::vector<std::string>& positions = forced_choice_positions(spec);

  TrialPlan plan;
  plan.trial_index = trials_done_;
  plan.procedure = experiment_.procedure;
  plan.condition_name = row.name();
  plan.staircase = track.name;
  plan.positions = positions;
  // The comparison's side is drawn per trial (trial_order stream), so side bias cannot track the
  // intensity.
  const bool comparison_left =
      CounterRandom(experiment_.seed, RandomStream::trial_order).uniform(static_cast<std::uint64_t>(trials_done_)) < 0.5;
  const double reference_cd_m2 = peak_of(peak_cd_m2_, reference);
  const double comparison_scale = intensity_cd_m2 / peak_of(peak_cd_m2_, comparison);
  plan.scenes = comparison_left ? std::vector<std::string>{comparison, reference}
                                : std::vector<std::string>{reference, comparison};
  plan.scene_scale = comparison_left ? std::vector<double>{comparison_scale, 1.0}
                                     : std::vector<double>{1.0, comparison_scale};
  plan.source_luminance_cd_m2 = comparison_left ? std::vector<double>{intensity_cd_m2, reference_cd_m2}
                                                : std::vector<double>{reference_cd_m2, intensity_cd_m2};
  plan.allowed_responses = spec.responses;
  const std::size_t comparison_position = comparison_left ? 0 : 1;
  plan.comparison_positions = {static_cast<int>(comparison_position)};
  // Relative 1e-9: the same luminance reached by different step paths is still equal.
  if (std::abs(intensity_cd_m2 - reference_cd_m2) <= 1e-9 * std::max(intensity_cd_m2, reference_cd_m2)) {
    plan.correct_response = spec.responses.size() == 3 ? spec.responses[2] : spec.responses[comparison_position];
  } else {
    plan.correct_response = spec.responses[intensity_cd_m2 > reference_cd_m2 ? comparison_position
                                                                             : 1 - comparison_position];
  }
  plan.intensity = intensity_cd_m2;
  plan.question = spec.question;
  plan.stimulus_frames = spec.stimulus_frames;

  JsonObjectWriter json;
  for (const auto& [column, value] : row.fields) json.add(column, value);
  json.add(positions[0], plan.scenes[0]).add(positions[1], plan.scenes[1]);
  json.add("staircase", track.name);
  plan.condition_json = json.str();
  return plan;
}

TrialOutcome AdaptiveProcedure::record_response(const TrialPlan& plan, const Response& response) {
  if (!current_ || plan.trial_index != trials_done_)
    throw std::logic_error("adaptive procedure: response to trial " + std::to_string(plan.trial_index) +
                           " is not for the trial planned next");
  TrialOutcome outcome;
  outcome.response = response.value;
  outcome.staircase = plan.staircase;
  // No answer within the response window: the trial is recorded unscored and the track does not
  // move; the same track shows the same intensity again on the next trial.
  if (response.value == kTimeoutResponse) {
    ++trials_done_;
    return outcome;
  }
  const auto& allowed = plan.allowed_responses;
  if (std::find(allowed.begin(), allowed.end(), response.value) == allowed.end()) return outcome;  // not an answer
  const bool correct = response.value == plan.correct_response;
  outcome.correct = correct ? 1 : 0;
  Track& track = tracks_[*current_];
  if (track.staircase) {
    outcome.reversal = track.staircase->add_response(correct) ? 1 : 0;
  } else {
    track.quest->add_response(correct);
    outcome.reversal = 0;  // QUEST has no reversals
  }
  current_.reset();
  ++trials_done_;
  return outcome;
}

}  // namespace glarelab
