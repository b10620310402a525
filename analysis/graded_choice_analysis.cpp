#include "analysis/graded_choice_analysis.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <set>

#include "core/parallel_for.h"

namespace glarelab::analysis {
namespace {

const std::vector<std::pair<std::string, std::string>> kPositionPairs = {{"left", "right"}, {"first", "second"}};

std::optional<double> number_text(const std::string& text) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

bool is_two_sided_choice(const LoadedTrial& trial) {
  return trial.record.procedure == "forced_choice" && trial.condition_value("scene_a") != nullptr &&
         trial.condition_value("scene_b") != nullptr;
}

// The condition keys that say where and how things are shown, never a graded variable.
bool is_layout_key(const std::string& key) {
  for (const auto& [first, second] : kPositionPairs)
    if (key == first || key == second) return true;
  return key.ends_with("_glare") || key == "name" || key == "scene_a" || key == "scene_b" || key == "scored";
}

// The position showing scene_b (by scene, else by glare), or nullptr when it cannot be told.
const std::string* position_of_b(const LoadedTrial& trial, const std::string** other) {
  const std::string& scene_b = *trial.condition_value("scene_b");
  const std::string& scene_a = *trial.condition_value("scene_a");
  const std::string* glare_a = trial.condition_value("glare_a");
  const std::string* glare_b = trial.condition_value("glare_b");
  const auto pick = [&](const std::string& b, const std::string& a) {
    *other = &a;
    return &b;
  };
  for (const auto& [first, second] : kPositionPairs) {
    const std::string* at_first = trial.condition_value(first);
    const std::string* at_second = trial.condition_value(second);
    if (at_first == nullptr || at_second == nullptr) continue;
    if (scene_a != scene_b) {
      if (*at_first == scene_b && *at_second == scene_a) return pick(first, second);
      if (*at_second == scene_b && *at_first == scene_a) return pick(second, first);
      return nullptr;
    }
    const std::string* glare_first = trial.condition_value(first + "_glare");
    const std::string* glare_second = trial.condition_value(second + "_glare");
    if (glare_a == nullptr || glare_b == nullptr || *glare_a == *glare_b || glare_first == nullptr ||
        glare_second == nullptr)
      return nullptr;
    if (*glare_first == *glare_b) return pick(first, second);
    if (*glare_second == *glare_b) return pick(second, first);
    return nullptr;
  }
  return nullptr;
}

// The first numeric condition column with three or more values over the two-sided forced-choice
// trials (numeric in every one of them).
std::string find_variable(const LoadedData& data) {
  std::vector<std::string> order;
  std::map<std::string, std::set<double>> values;
  std::set<std::string> not_numeric;
  for (const LoadedSession& session : data.sessions) {
    for (const LoadedTrial& trial : session.trials) {
      if (!is_two_sided_choice(trial)) continue;
      std::set<std::string> seen;
      for (const auto& [key, text] : trial.condition) {
        if (is_layout_key(key)) continue;
        seen.insert(key);
        if (std::find(order.begin(), order.end(), key) == order.end()) order.push_back(key);
        if (const std::optional<double> value = number_text(text)) values[key].insert(*value);
        else not_numeric.insert(key);
      }
      for (const std::string& key : order)
        if (!seen.contains(key)) not_numeric.insert(key);  // missing in this trial
    }
  }
  for (const std::string& key : order)
    if (!not_numeric.contains(key) && values[key].size() >= 3) return key;
  return {};
}

std::string group_of(const LoadedTrial& trial, bool glare_b_varies) {
  if (const std::string* glare = trial.condition_value("glare")) return *glare;
  const std::string* glare_a = trial.condition_value("glare_a");
  const std::string* glare_b = trial.condition_value("glare_b");
  if (glare_a != nullptr && glare_b != nullptr) return glare_b_varies ? *glare_a + " / " + *glare_b : *glare_a;
  return "all trials";
}

}  // namespace

std::optional<double> GradedChoiceGroup::pse() const {
  if (fit.ok()) return fit.threshold;
  if (posterior) return posterior->median;
  return std::nullopt;
}

std::string GradedChoiceAnalysis::axis_label() const { return log10_axis ? "log10 " + variable : variable; }

bool is_graded_trial(const LoadedTrial& trial, const GradedChoiceAnalysis& analysis) {
  if (analysis.variable.empty() || !is_two_sided_choice(trial)) return false;
  const std::string* text = trial.condition_value(analysis.variable);
  return text != nullptr && number_text(*text).has_value();
}

GradedChoiceAnalysis analyse_graded_choice(const LoadedData& data, const GradedChoiceOptions& options) {
  GradedChoiceAnalysis analysis;
  analysis.variable = find_variable(data);
  if (analysis.variable.empty()) return analysis;
  analysis.log10_axis = analysis.variable.find("ratio") != std::string::npos;

  std::set<std::string> glare_b_values;
  for (const LoadedSession& session : data.sessions)
    for (const LoadedTrial& trial : session.trials)
      if (is_graded_trial(trial, analysis))
        if (const std::string* glare_b = trial.condition_value("glare_b")) glare_b_values.insert(*glare_b);
  const bool glare_b_varies = glare_b_values.size() > 1;

  std::vector<std::string> group_order;
  std::map<std::string, std::vector<std::pair<double, bool>>> answers;
  std::map<std::string, long> neither;
  std::map<std::pair<std::string, std::string>, std::vector<std::pair<double, bool>>> participant_answers;
  std::vector<std::pair<std::string, std::string>> participant_order;
  long unplaced = 0, not_positive = 0;
  for (const LoadedSession& session : data.sessions) {
    for (const LoadedTrial& trial : session.trials) {
      if (!is_graded_trial(trial, analysis)) continue;
      if (analysis.sessions.empty() || analysis.sessions.back() != session.label) analysis.sessions.push_back(session.label);
      ++analysis.trials;
      double x = *number_text(*trial.condition_value(analysis.variable));
      if (analysis.log10_axis) {
        if (!(x > 0.0)) {
          ++not_positive;
          continue;
        }
        x = std::log10(x);
      }
      const std::string* other = nullptr;
      const std::string* b = position_of_b(trial, &other);
      if (b == nullptr) {
        ++unplaced;
        continue;
      }
      const std::string group = group_of(trial, glare_b_varies);
      if (std::find(group_order.begin(), group_order.end(), group) == group_order.end()) group_order.push_back(group);
      const std::string& response = trial.record.response;
      if (response == *b || response == *other) {
        answers[group].emplace_back(x, response == *b);
        const std::pair<std::string, std::string> cell{session.record.participant, group};
        auto& cell_answers = participant_answers[cell];
        if (cell_answers.empty()) participant_order.push_back(cell);
        cell_answers.emplace_back(x, response == *b);
      }
      else if (response == "neither") ++neither[group];
    }
  }
  if (unplaced > 0)
    analysis.notes.push_back(std::to_string(unplaced) + " trial(s) left out: scene_b's side could not be told (the same scene "
                                                        "and glare on both sides, or positions not stored)");
  if (not_positive > 0)
    analysis.notes.push_back(std::to_string(not_positive) + " trial(s) left out: " + analysis.variable +
                             " is not positive, so it has no log10");

  // The baseline ("control") first, then the other groups alphabetically: the same order whatever
  // the trial order.
  std::sort(group_order.begin(), group_order.end(), [](const std::string& a, const std::string& b) {
    return std::pair(a != "control", a) < std::pair(b != "control", b);
  });
  for (const std::string& name : group_order) {
    GradedChoiceGroup group;
    group.name = name;
    group.levels = levels_from_trials(answers[name]);
    group.neither = neither[name];
    analysis.groups.push_back(std::move(group));
  }
  std::vector<PsychometricFit> fits(analysis.groups.size());
  parallel_for(analysis.groups.size(), options.threads, [&](std::size_t g) {
    PsychometricFitOptions fit_options;
    fit_options.shape = PsychometricShape::cumulative_normal;
    fit_options.guess_rate = 0.0;
    fit_options.lapse_max = 0.0;
    fit_options.bootstrap_samples = options.bootstrap_samples;
    fit_options.seed = options.seed + g;
    fits[g] = fit_psychometric(analysis.groups[g].levels, fit_options);
    analysis.groups[g].posterior = pse_posterior(analysis.groups[g].levels);
    analysis.groups[g].psignifit = psignifit_pse(analysis.groups[g].levels);
  });
  for (std::size_t g = 0; g < fits.size(); ++g) analysis.groups[g].fit = std::move(fits[g]);

  const auto control = std::find_if(analysis.groups.begin(), analysis.groups.end(),
                                    [](const GradedChoiceGroup& g) { return g.name == "control"; });
  const GradedChoiceGroup& baseline = control != analysis.groups.end() ? *control : analysis.groups.front();
  analysis.baseline = baseline.name;
  parallel_for(analysis.groups.size(), options.threads, [&](std::size_t g) {
    GradedChoiceGroup& group = analysis.groups[g];
    if (&group == &baseline || !group.pse() || !baseline.pse()) return;
    group.shift = *group.pse() - *baseline.pse();
    if (group.posterior && baseline.posterior)
      group.shift_interval = pse_shift_credible_interval(*baseline.posterior, *group.posterior);
  });
  std::vector<ParticipantCell> cells;
  for (const auto& key : participant_order) {
    ParticipantCell cell;
    cell.participant = key.first;
    cell.group = key.second;
    cell.levels = levels_from_trials(participant_answers[key]);
    cells.push_back(std::move(cell));
  }
  analysis.within = analyse_within_participants(std::move(cells), group_order, analysis.baseline, options.threads);
  if (analysis.groups.size() >= 2) {
    std::vector<std::vector<StimulusLevel>> levels;
    for (const GradedChoiceGroup& group : analysis.groups) levels.push_back(group.levels);
    analysis.shared_pse = shared_pse_test(levels);
  }
  return analysis;
}

}  // namespace glarelab::analysis
