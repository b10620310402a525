#include "protocols/forced_choice.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "protocols/blocked_design.h"
#include "protocols/fixed_design_procedure.h"
#include "protocols/glare_config.h"
#include "protocols/json_text.h"
#include "core/random.h"

namespace glarelab {
namespace {

// One planned presentation before shuffling: which row, and whether scene_a goes right.
struct Presentation {
  std::size_t row = 0;
  bool swapped = false;
};

double peak_of(const std::map<std::string, double>& source_peak_cd_m2, const std::string& scene) {
  const auto found = source_peak_cd_m2.find(scene);
  if (found == source_peak_cd_m2.end()) {
    throw std::invalid_argument("forced choice: no peak luminance for scene '" + scene + "'");
  }
  return found->second;
}

// Equal within a relative 1e-9: the same source rendered twice must not count as a difference
// that an observer could get right or wrong.
bool nearly_equal(double a, double b) {
  return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b));
}

}  // namespace

const std::vector<std::string>& forced_choice_positions(const ForcedChoiceSpec& spec) {
  static const std::vector<std::string> side_by_side = {"left", "right"};
  static const std::vector<std::string> sequential = {"first", "second"};
  return spec.layout == "sequential" ? sequential : side_by_side;
}

std::vector<std::string> default_responses_for(const ForcedChoiceSpec& spec) {
  std::vector<std::string> responses = forced_choice_positions(spec);
  if (spec.alternatives == 3) responses.push_back("neither");
  return responses;
}

namespace {

// The design in the session's order, a row index and a side per trial, and what planning a trial
// from them needs. It reads the condition rows where the experiment holds them (a move of the
// Experiment leaves them in place), so a million rows are not copied for two million plans.
class ForcedChoiceDesign {
 public:
  ForcedChoiceDesign(const Experiment& experiment, const std::map<std::string, double>& source_peak_cd_m2)
      : rows_(experiment.conditions.data()),
        spec_(experiment.forced_choice),
        positions_(forced_choice_positions(spec_)),
        peak_cd_m2_(source_peak_cd_m2) {
    // One response per position, plus "neither" in the 3-way variant (Spencer 1995).
    if (spec_.responses.size() != positions_.size() && spec_.responses.size() != positions_.size() + 1) {
      throw std::invalid_argument("forced choice: expected " + std::to_string(positions_.size()) + " or " +
                                  std::to_string(positions_.size() + 1) + " responses");
    }
    // Every row's scenes and their peaks, checked here, so that planning a trial later cannot fail.
    for (const ConditionRow& row : experiment.conditions) {
      const std::string* scene_a = row.find("scene_a");
      const std::string* scene_b = row.find("scene_b");
      if (scene_a == nullptr || scene_b == nullptr) {
        throw std::invalid_argument("forced choice: condition '" + row.name() + "' lacks scene_a or scene_b");
      }
      peak_of(peak_cd_m2_, *scene_a);
      peak_of(peak_cd_m2_, *scene_b);
    }
    // Counterbalancing shows every pair both ways round, so a side bias of the observer adds
    // equally to both and cancels in the proportion correct.
    design_ = order_fixed_design<Presentation>(
        experiment, spec_.repetitions, [&](const std::vector<std::size_t>& rows, int repetitions) {
          std::vector<Presentation> units;
          units.reserve(rows.size() * static_cast<std::size_t>(repetitions) * (spec_.counterbalance_sides ? 2 : 1));
          for (const std::size_t row : rows) {
            for (int repetition = 0; repetition < repetitions; ++repetition) {
              units.push_back({row, false});
              if (spec_.counterbalance_sides) units.push_back({row, true});
            }
          }
          return units;
        });
  }

  std::size_t size() const { return design_.size(); }
  TrialPlan plan(std::size_t index) const;

 private:
  const ConditionRow* rows_;
  ForcedChoiceSpec spec_;
  std::vector<std::string> positions_;
  std::map<std::string, double> peak_cd_m2_;
  OrderedDesign<Presentation> design_;
};

TrialPlan ForcedChoiceDesign::plan(std::size_t index) const {
  const Presentation& presentation = design_.unit(index);
  const ConditionRow& row = rows_[presentation.row];
  const std::string& scene_a = *row.find("scene_a");
  const std::string& scene_b = *row.find("scene_b");

  TrialPlan plan;
  plan.trial_index = static_cast<int>(index);
  plan.procedure = "forced_choice";
  plan.condition_name = row.name();
  plan.positions = positions_;
  plan.scenes = presentation.swapped ? std::vector<std::string>{scene_b, scene_a}
                                     : std::vector<std::string>{scene_a, scene_b};
  for (const std::string& scene : plan.scenes) plan.source_luminance_cd_m2.push_back(peak_of(peak_cd_m2_, scene));
  // Position i is answered by responses[i] (e.g. "left" or a key name chosen in the file).
  plan.allowed_responses = spec_.responses;
  const double left = plan.source_luminance_cd_m2[0];
  const double right = plan.source_luminance_cd_m2[1];
  // Preference questions ("which is more attractive?") have no right answer: a row with
  // scored = false leaves `correct` NULL whatever the luminances.
  const std::string* scored = row.find("scored");
  const bool has_answer = scored == nullptr || *scored != "false";
  if (!has_answer) {
    // no correct response
  } else if (!nearly_equal(left, right)) {
    plan.correct_response = spec_.responses[left > right ? 0 : 1];
  } else if (spec_.responses.size() == 3) {
    plan.correct_response = spec_.responses[2];  // equal sources: "neither" is the right answer
  }
  // A "question" column asks each row its own question (Ritschel 2009: brighter, more
  // attractive, more realistic), shown above the stimuli.
  const std::string* question = row.find("question");
  plan.question = question != nullptr ? *question : spec_.question;
  apply_block_placement(design_.placement(index), question != nullptr, plan);
  // What each side shows, by the names of the row's condition_a / condition_b columns (Ritschel's
  // dynamic, static, control): the simulated observer's preferences are between these.
  const std::string* condition_a = row.find("condition_a");
  const std::string* condition_b = row.find("condition_b");
  if (condition_a != nullptr && condition_b != nullptr) {
    plan.position_conditions = presentation.swapped ? std::vector<std::string>{*condition_b, *condition_a}
                                                    : std::vector<std::string>{*condition_a, *condition_b};
  }
  // A glare mode per side (glare_a / glare_b): follows its scene when the sides are swapped.
  if (const auto modes = position_glare_modes(row)) {
    const std::string a = to_string(modes->first), b = to_string(modes->second);
    plan.position_glare = presentation.swapped ? std::vector<std::string>{b, a} : std::vector<std::string>{a, b};
  }
  plan.stimulus_frames = spec_.stimulus_frames;

  JsonObjectWriter json;
  for (const auto& [column, value] : row.fields) json.add(column, value);
  json.add(positions_[0], plan.scenes[0]).add(positions_[1], plan.scenes[1]);
  // What the analysis compares when both sides show one scene: "left_glare", "right_glare".
  for (std::size_t p = 0; p < plan.position_glare.size(); ++p) json.add(positions_[p] + "_glare", plan.position_glare[p]);
  plan.condition_json = json.str();
  return plan;
}

}  // namespace

std::vector<TrialPlan> build_forced_choice_trials(const Experiment& experiment,
                                                  const std::map<std::string, double>& source_peak_cd_m2) {
  const ForcedChoiceDesign design(experiment, source_peak_cd_m2);
  std::vector<TrialPlan> trials;
  trials.reserve(design.size());
  for (std::size_t index = 0; index < design.size(); ++index) trials.push_back(design.plan(index));
  return trials;
}

std::unique_ptr<Procedure> make_forced_choice_procedure(const Experiment& experiment,
                                                        const std::map<std::string, double>& source_peak_cd_m2) {
  auto design = std::make_shared<const ForcedChoiceDesign>(experiment, source_peak_cd_m2);
  const std::size_t trial_count = design->size();
  return std::make_unique<FixedDesignProcedure>(
      trial_count, [design](std::size_t index) { return design->plan(index); }, score_forced_choice);
}

TrialOutcome score_forced_choice(const TrialPlan& plan, const Response& response) {
  TrialOutcome outcome;
  outcome.response = response.value;
  if (plan.correct_response.empty()) return outcome;  // equal sources: no answer is right
  if (response.value == plan.correct_response) {
    outcome.correct = 1;
  } else if (std::find(plan.allowed_responses.begin(), plan.allowed_responses.end(), response.value) !=
             plan.allowed_responses.end()) {
    outcome.correct = 0;
  }
  // Anything else ("abort") is not an answer and stays unscored.
  return outcome;
}

}  // namespace glarelab
