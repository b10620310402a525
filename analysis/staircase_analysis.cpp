#include "analysis/staircase_analysis.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <map>
#include <optional>
#include <string>

#include "analysis/pse_analysis.h"
#include "analysis/stored_procedure.h"
#include "core/parallel_for.h"

namespace glarelab::analysis {
namespace {

// Guess rate fixed by the task: condition "guess_rate", else 1 / the condition's "alternatives",
// else 1 / the procedure's stored `alternatives` (a 3-way task with "neither" guesses 1/3), else 2AFC.
double guess_rate_of(const LoadedTrial& trial, const std::string& config_toml, std::string& note) {
  if (const std::string* value = trial.condition_value("guess_rate")) {
    char* end = nullptr;
    const double rate = std::strtod(value->c_str(), &end);
    if (end != value->c_str() && rate >= 0.0 && rate < 1.0) return rate;
  }
  if (const std::string* value = trial.condition_value("alternatives")) {
    const long alternatives = std::strtol(value->c_str(), nullptr, 10);
    if (alternatives >= 2) return 1.0 / static_cast<double>(alternatives);
  }
  if (const std::optional<int> alternatives = stored_alternatives(config_toml)) {
    note = "guess rate 1/" + std::to_string(*alternatives) + " from the procedure's alternatives = " +
           std::to_string(*alternatives);
    return 1.0 / static_cast<double>(*alternatives);
  }
  note = "guess rate 0.5 assumed (two-alternative task; neither the condition nor the stored procedure names a "
         "guess_rate or alternatives)";
  return 0.5;
}

}  // namespace

PsignifitOptions staircase_psignifit_options(double guess_rate) {
  PsignifitOptions options;
  options.sigmoid = PsignifitSigmoid::norm;
  const double alternatives = 1.0 / guess_rate;
  if (guess_rate > 0.0 && std::abs(alternatives - std::round(alternatives)) < 1e-9 && std::round(alternatives) >= 2.0) {
    options.experiment = PsignifitExperiment::n_afc;
    options.alternatives = static_cast<int>(std::round(alternatives));
  } else {
    options.experiment = PsignifitExperiment::yes_no;
    options.fixed[3] = guess_rate;
  }
  return options;
}

std::vector<StaircaseResult> analyse_staircases(const LoadedData& data, const StaircaseOptions& options) {
  std::vector<StaircaseResult> results;
  // The fits (the bulk of the analysis time: each bootstrap replicate is a full ML fit) are
  // collected first and run on worker threads; each is seeded by its staircase, not by the order
  // in which threads reach it.
  struct FitJob {
    std::size_t result;
    std::vector<StimulusLevel> levels;
    PsychometricFitOptions options;
  };
  std::vector<FitJob> jobs;
  for (std::size_t s = 0; s < data.sessions.size(); ++s) {
    const LoadedSession& session = data.sessions[s];
    std::map<std::string, std::size_t> index_of;
    const std::size_t first = results.size();
    for (const LoadedTrial& trial : session.trials) {
      const TrialRecord& r = trial.record;
      if (r.procedure != "staircase" && r.procedure != "quest") continue;
      if (is_pse_trial(trial)) continue;  // unscored appearance judgements: analysis/pse_analysis.h
      // QUEST+ and Psi tracks (stored as procedure "quest" with their method) are analysed by their
      // own posterior alone (analysis/quest_plus_posterior.h): their placements are not a staircase,
      // have no reversals, and are in the procedure's stimulus unit.
      if (const std::string* method = trial.condition_value("method"); method && (*method == "quest_plus" || *method == "psi"))
        continue;
      std::string name = r.staircase;
      if (name.empty()) {
        const std::string* condition_name = trial.condition_value("name");
        name = condition_name != nullptr ? *condition_name : r.procedure;
      }
      auto [found, inserted] = index_of.try_emplace(r.procedure + "\x1f" + name, results.size());
      if (inserted) {
        StaircaseResult result;
        result.participant_label = session.label;
        result.name = name;
        result.procedure = r.procedure;
        result.guess_rate = guess_rate_of(trial, session.record.config, result.guess_note);
        results.push_back(std::move(result));
      }
      StaircaseResult& result = results[found->second];
      if (!r.intensity || !r.correct) continue;  // unanswered (aborted) trial
      result.track.push_back({r.trial_index, *r.intensity, *r.correct == 1, r.reversal.value_or(0) == 1});
    }
    for (std::size_t i = first; i < results.size(); ++i) {
      StaircaseResult& result = results[i];
      std::vector<double> reversal_intensities;
      for (const StaircasePoint& point : result.track) {
        if (point.reversal) reversal_intensities.push_back(point.intensity);
      }
      result.reversals = static_cast<int>(reversal_intensities.size());
      if (result.track.empty()) {
        result.threshold_note = "no answered trials";
      } else if (reversal_intensities.empty()) {
        result.threshold_note = "staircase never reversed: no reversal threshold (" + std::to_string(result.track.size()) +
                                " trials)";
      } else {
        const int k = std::min<int>(options.last_reversals, result.reversals);
        double sum = 0.0;
        for (int j = result.reversals - k; j < result.reversals; ++j) sum += reversal_intensities[static_cast<std::size_t>(j)];
        result.reversal_threshold = sum / k;
        result.reversals_used = k;
        if (k < options.last_reversals) {
          result.threshold_note = "only " + std::to_string(k) + " reversal(s): mean of all of them (asked for the last " +
                                  std::to_string(options.last_reversals) + ")";
        }
      }
      if (result.procedure == "quest" && !result.track.empty()) result.quest_estimate = result.track.back().intensity;
      std::vector<std::pair<double, bool>> trials;
      for (const StaircasePoint& point : result.track) trials.emplace_back(point.intensity, point.correct);
      const auto levels = levels_from_trials(trials);
      for (PsychometricShape shape :
           {PsychometricShape::logistic, PsychometricShape::cumulative_normal, PsychometricShape::weibull}) {
        PsychometricFitOptions fit_options;
        fit_options.shape = shape;
        fit_options.guess_rate = result.guess_rate;
        fit_options.bootstrap_samples = options.bootstrap_samples;
        fit_options.seed = options.seed + i;
        jobs.push_back({i, levels, fit_options});
      }
    }
  }
  std::vector<PsychometricFit> fits(jobs.size());
  parallel_for(jobs.size(), options.threads,
               [&](std::size_t j) { fits[j] = fit_psychometric(jobs[j].levels, jobs[j].options); });
  for (std::size_t j = 0; j < jobs.size(); ++j) results[jobs[j].result].fits.push_back(std::move(fits[j]));
  parallel_for(results.size(), options.threads, [&](std::size_t i) {
    StaircaseResult& result = results[i];
    std::vector<PsignifitBlock> blocks;
    std::vector<std::pair<double, bool>> trials;
    for (const StaircasePoint& point : result.track) trials.emplace_back(point.intensity, point.correct);
    for (const StimulusLevel& level : levels_from_trials(trials)) blocks.push_back({level.intensity, level.correct, level.trials});
    try {
      result.psignifit = psignifit_fit(blocks, staircase_psignifit_options(result.guess_rate));
    } catch (const std::invalid_argument& error) {
      result.psignifit_note = std::string("no psignifit fit: ") + error.what();
    }
  });
  return results;
}

}  // namespace glarelab::analysis
