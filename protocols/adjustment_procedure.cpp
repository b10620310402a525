#include "protocols/adjustment_procedure.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/number_text.h"
#include "protocols/blocked_design.h"
#include "protocols/fixed_design_procedure.h"
#include "protocols/json_text.h"
#include "core/random.h"

namespace glarelab {
namespace {

double peak_of(const std::map<std::string, double>& peaks, const std::string& scene) {
  const auto found = peaks.find(scene);
  if (found == peaks.end() || !(found->second > 0.0))
    throw std::invalid_argument("adjustment: scene '" + scene + "' has no positive peak luminance to scale");
  return found->second;
}

std::string seventeen_digit_text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

}  // namespace

void read_adjustment_procedure(TableReader& procedure, Experiment& experiment) {
  AdjustmentSpec& spec = experiment.adjustment;
  spec.coarse_step_log10 = procedure.positive_number("coarse_step_log10", spec.coarse_step_log10);
  spec.fine_step_log10 = procedure.positive_number("fine_step_log10", spec.fine_step_log10);
  if (const auto range = procedure.number("start_range_log10")) {
    if (!(*range >= 0.0)) procedure.fail("start_range_log10", "must be >= 0, found " + number_text(*range));
    spec.start_range_log10 = *range;
  }
  spec.repetitions = procedure.repetitions("repetitions", spec.repetitions);
}

std::vector<TrialPlan> build_adjustment_trials(const Experiment& experiment,
                                               const std::map<std::string, double>& source_peak_cd_m2) {
  const AdjustmentSpec& spec = experiment.adjustment;
  const auto design = order_fixed_design<std::size_t>(
      experiment, spec.repetitions, [](const std::vector<std::size_t>& rows, int repetitions) {
        std::vector<std::size_t> units;
        for (const std::size_t row : rows)
          for (int repetition = 0; repetition < repetitions; ++repetition) units.push_back(row);
        return units;
      });

  const CounterRandom start_random(experiment.seed, RandomStream::adjustment_start);
  std::vector<TrialPlan> trials;
  for (std::size_t index = 0; index < design.size(); ++index) {
    const ConditionRow& row = experiment.conditions[design.unit(index)];
    const std::string* target = row.find("target");
    const std::string* comparison = row.find("comparison");
    if (target == nullptr || comparison == nullptr)
      throw std::invalid_argument("adjustment: condition '" + row.name() + "' lacks target or comparison");
    const double target_cd_m2 = peak_of(source_peak_cd_m2, *target);
    const double comparison_peak_cd_m2 = peak_of(source_peak_cd_m2, *comparison);
    TrialPlan plan;
    plan.trial_index = static_cast<int>(index);
    plan.procedure = "adjustment";
    plan.condition_name = row.name();
    plan.positions = {"left", "target", "right"};
    plan.scenes = {*comparison, *target, *comparison};
    // Start values log-uniform within +-start_range_log10 of the target, but never above the display's
    // peak: a spot drawn brighter than the display can show starts clipped, and the first steps
    // down change nothing the observer can see. The range is then [target - r, peak] in log10.
    const double above_log10 = std::min(spec.start_range_log10,
                                        std::max(-spec.start_range_log10,
                                                 std::log10(experiment.display.peak_luminance_cd_m2 / target_cd_m2)));
    for (std::uint32_t spot = 0; spot < 2; ++spot) {
      const double uniform = start_random.uniform(index, spot);
      const double u = 2.0 * uniform - 1.0;
      plan.adjustment_start_cd_m2.push_back(
          above_log10 >= spec.start_range_log10
              ? target_cd_m2 * std::pow(10.0, spec.start_range_log10 * u)
              : target_cd_m2 * std::pow(10.0, -spec.start_range_log10 + (spec.start_range_log10 + above_log10) * uniform));
    }
    const double left = plan.adjustment_start_cd_m2[0];
    const double right = plan.adjustment_start_cd_m2[1];
    plan.scene_scale = {left / comparison_peak_cd_m2, 1.0, right / comparison_peak_cd_m2};
    plan.source_luminance_cd_m2 = {left, target_cd_m2, right};
    plan.comparison_positions = {0, 2};
    plan.question = "Adjust both spots until they look as bright as the centre (up/down: coarse, "
                    "right/left: fine; Enter or Space when they match)";
    plan.stimulus_frames = experiment.forced_choice.stimulus_frames;
    apply_block_placement(design.placement(index), false, plan);
    JsonObjectWriter json;
    for (const auto& [column, value] : row.fields) json.add(column, value);
    json.add("start_left_cd_m2", seventeen_digit_text(left)).add("start_right_cd_m2", seventeen_digit_text(right));
    plan.condition_json = json.str();
    trials.push_back(std::move(plan));
  }
  return trials;
}

std::string format_adjustment_response(double left_cd_m2, double right_cd_m2) {
  return seventeen_digit_text(left_cd_m2) + " " + seventeen_digit_text(right_cd_m2);
}

TrialOutcome score_adjustment(const TrialPlan& plan, const Response& response) {
  TrialOutcome outcome;
  outcome.response = response.value;
  if (response.value == "abort") return outcome;
  std::istringstream in(response.value);
  std::vector<double> settings;
  double value = 0.0;
  while (in >> value) settings.push_back(value);
  in.clear();
  std::string rest;
  in >> rest;
  if (settings.size() == 1) settings.push_back(settings[0]);  // one number sets both spots
  if (settings.size() != 2 || !rest.empty() || !(settings[0] > 0.0) || !(settings[1] > 0.0) ||
      !std::isfinite(settings[0]) || !std::isfinite(settings[1])) {
    throw std::invalid_argument("adjustment: trial " + std::to_string(plan.trial_index) + ": response '" +
                                response.value + "' is not one or two positive luminances in cd/m2");
  }
  outcome.adjustment_settings_cd_m2 = settings;
  // The perceived luminance is the mean of the two settings (Ritschel et al. 2009, 6.1).
  outcome.intensity = 0.5 * (settings[0] + settings[1]);
  return outcome;
}

std::unique_ptr<Procedure> make_adjustment_procedure(const Experiment& experiment,
                                                     const std::map<std::string, double>& source_peak_cd_m2) {
  return std::make_unique<FixedDesignProcedure>(build_adjustment_trials(experiment, source_peak_cd_m2),
                                                score_adjustment);
}

}  // namespace glarelab
