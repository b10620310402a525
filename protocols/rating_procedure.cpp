#include "protocols/rating_procedure.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "core/number_text.h"
#include "core/real_stimulus.h"
#include "protocols/blocked_design.h"
#include "protocols/fixed_design_procedure.h"
#include "protocols/json_text.h"
#include "core/random.h"

namespace glarelab {

void read_rating_procedure(TableReader& procedure, Experiment& experiment) {
  RatingSpec& spec = experiment.rating;
  const auto categories = procedure.distinct_names("categories", "category");
  if (!categories)
    procedure.fail("categories", "missing required key (the named categories to rate, e.g. [\"glare appearance\"])");
  for (const ArrayString& name : *categories) spec.categories.push_back(name.value);
  if (spec.categories.empty()) procedure.fail("categories", "at least one category is required");
  if (const auto points = procedure.integer("scale_points")) {
    // Answered with the digit keys 1..9.
    if (*points < 2 || *points > 9) procedure.fail("scale_points", "must be 2..9, found " + number_text(*points));
    spec.scale_points = static_cast<int>(*points);
  }
  spec.repetitions = procedure.repetitions("repetitions", spec.repetitions);
  if (const toml::table* labels = procedure.table("category_labels")) {
    for (const auto& [key, value] : *labels) {
      const std::string category(key.str());
      if (std::find(spec.categories.begin(), spec.categories.end(), category) == spec.categories.end())
        throw ConfigError(to_location(key.source(), procedure.file()), procedure.key_path("category_labels") + "." + category,
                          "not one of the categories");
      const std::string* text = value.is_string() ? &value.as_string()->get() : nullptr;
      if (text == nullptr || text->empty())
        throw ConfigError(to_location(value.source(), procedure.file()), procedure.key_path("category_labels") + "." + category,
                          "expected the category's name in the question, a non-empty string");
      spec.category_labels[category] = *text;
    }
  }
  if (const toml::array* anchors = procedure.array("scale_anchors")) {
    if (anchors->size() != 2)
      procedure.fail("scale_anchors", "expected two texts, what 1 and what " + std::to_string(spec.scale_points) +
                                          " mean (e.g. [\"completely different\", \"exactly the same\"]), found " +
                                          std::to_string(anchors->size()));
    for (std::size_t i = 0; i < anchors->size(); ++i) {
      const std::string& text =
          expect_string(*anchors->get(i), procedure.key_path("scale_anchors") + "[" + std::to_string(i) + "]",
                        procedure.file());
      if (text.empty()) procedure.fail("scale_anchors", "anchor texts must not be empty");
      spec.scale_anchors.push_back(text);
    }
  }
}

std::string rating_question(const RatingSpec& spec, const std::string& category_name) {
  const auto label = spec.category_labels.find(category_name);
  const std::string& category = label == spec.category_labels.end() ? category_name : label->second;
  const std::string top = std::to_string(spec.scale_points);
  if (spec.scale_anchors.empty()) return "Rate the " + category + " from 1 to " + top;
  return "Rate the " + category + " from 1 (" + spec.scale_anchors[0] + ") to " + top + " (" + spec.scale_anchors[1] +
         ")";
}

std::vector<TrialPlan> build_rating_trials(const Experiment& experiment) {
  const RatingSpec& spec = experiment.rating;
  struct Presentation {
    std::size_t row;
    std::size_t category;
  };
  const auto design = order_fixed_design<Presentation>(
      experiment, spec.repetitions, [&](const std::vector<std::size_t>& rows, int repetitions) {
        std::vector<Presentation> units;
        for (const std::size_t row : rows)
          for (std::size_t category = 0; category < spec.categories.size(); ++category)
            for (int repetition = 0; repetition < repetitions; ++repetition) units.push_back({row, category});
        return units;
      });

  std::vector<std::string> allowed;
  for (int point = 1; point <= spec.scale_points; ++point) allowed.push_back(std::to_string(point));
  std::vector<TrialPlan> trials;
  for (std::size_t index = 0; index < design.size(); ++index) {
    const ConditionRow& row = experiment.conditions[design.unit(index).row];
    const std::string& category = spec.categories[design.unit(index).category];
    const std::string* scene = row.find("scene");
    if (scene == nullptr) throw std::invalid_argument("rating: condition '" + row.name() + "' lacks scene");
    TrialPlan plan;
    plan.trial_index = static_cast<int>(index);
    plan.procedure = "rating";
    plan.condition_name = row.name();
    plan.positions = {"centre"};
    plan.scenes = {*scene};
    plan.real_stimulus = real_stimulus_object(*scene);
    plan.allowed_responses = allowed;
    plan.question = rating_question(spec, category);
    plan.stimulus_frames = experiment.forced_choice.stimulus_frames;
    apply_block_placement(design.placement(index), false, plan);
    if (const std::string* mean = row.find("simulated_rating")) {
      try {
        plan.simulated_rating_mean = std::stod(*mean);
      } catch (const std::exception&) {
        throw std::invalid_argument("rating: condition '" + row.name() + "': simulated_rating '" + *mean +
                                    "' is not a number");
      }
    } else {
      plan.simulated_rating_mean = (1.0 + spec.scale_points) / 2.0;
    }
    JsonObjectWriter json;
    for (const auto& [column, value] : row.fields) json.add(column, value);
    json.add("category", category);
    // The trial record says the stimulus was the object itself, not an image of it.
    if (!plan.real_stimulus.empty()) json.add("stimulus", "real");
    plan.condition_json = json.str();
    trials.push_back(std::move(plan));
  }
  return trials;
}

std::unique_ptr<Procedure> make_rating_procedure(const Experiment& experiment) {
  return std::make_unique<FixedDesignProcedure>(build_rating_trials(experiment),
                                                [](const TrialPlan&, const Response& response) {
                                                  TrialOutcome outcome;
                                                  outcome.response = response.value;
                                                  return outcome;  // a rating has no right answer
                                                });
}

}  // namespace glarelab
