#include "runner/cli/quest_plus_posteriors.h"

#include <stdexcept>

#include "runner/session/scene_places.h"
#include "runner/session/session_setup.h"
#include "stimuli/scene_library.h"

namespace glarelab {
namespace {

// The unit of QUEST+ intensities (protocols/adaptive_procedure.h, quest_plus_luminance_cd_m2).
std::string intensity_unit_label(const std::string& intensity_unit) {
  if (intensity_unit == "db_cd_m2") return "dB cd/m2";
  if (intensity_unit == "log10_cd_m2") return "log10 cd/m2";
  return intensity_unit;
}

// A parameter's unit, from its role in the psychometric function (protocols/quest_plus.h):
// thresholds and the normal's SD are intensities; a threshold coefficient is intensity per unit
// of its stimulus column; the logistic's slope is per intensity unit, the Weibull's a pure number
// (it multiplies a dB difference / 20, a log10 difference or the exponent of a ratio); guess and
// lapse are probabilities.
std::string parameter_unit(const QuestPlusSpec& spec, const ParameterAxis& axis, const std::string& intensity) {
  switch (axis.role) {
    case ParameterRole::threshold:
    case ParameterRole::threshold_floor:
    case ParameterRole::sd:
      return intensity;
    case ParameterRole::threshold_coefficient:
      return intensity + " per " + spec.stimulus.at(axis.stimulus_dimension).name;
    case ParameterRole::slope:
      return spec.shape == PsychometricShape::logistic ? "per " + intensity : "no unit";
    case ParameterRole::guess:
    case ParameterRole::lapse:
      return "probability";
  }
  return "";
}

}  // namespace

bool runs_quest_plus(const analysis::LoadedSession& session) {
  for (const analysis::LoadedTrial& trial : session.trials) {
    if (trial.record.procedure != "quest") continue;
    const std::string* method = trial.condition_value("method");
    if (method && (*method == "quest_plus" || *method == "psi")) return true;
  }
  return false;
}

ReplayedSession replay_stored_session(const analysis::LoadedSession& session) {
  // What load_session_start does for --resume: the stored, fully resolved design.
  SessionStart start;
  start.db_path = session.database;
  start.resumed = session.record;
  start.experiment =
      parse_experiment_text(session.record.config, "<session " + std::to_string(session.record.id) + " config>", "/");
  for (const analysis::LoadedTrial& trial : session.trials) start.done_trials.push_back(trial.record);
  SceneLibrary scenes(start.experiment.scenes, start.experiment.display);
  fit_scenes_to_places(start.experiment, scenes, /*refuse_misfits=*/false);  // the peaks the session's procedure was made with
  ReplayedSession replayed;
  replayed.procedure = make_procedure(start.experiment, scenes.peak_luminances_cd_m2());
  replay_done_trials(*replayed.procedure, start);
  replayed.experiment = std::move(start.experiment);
  return replayed;
}

std::vector<analysis::QuestPlusPosterior> quest_plus_posteriors_of(const AdaptiveProcedure& procedure,
                                                                   const Experiment& experiment,
                                                                   const std::string& participant_label) {
  std::vector<analysis::QuestPlusPosterior> tracks;
  for (std::size_t t = 0; t < procedure.track_count(); ++t) {
    const QuestPlus* q = procedure.quest_plus(t);
    if (!q) continue;
    const QuestPlusSpec& spec = q->spec();
    std::string intensity_unit = "db_cd_m2";
    for (const AdaptiveTrackSpec& track : experiment.adaptive.tracks)
      if (track.quest_plus.spec.name == spec.name) intensity_unit = track.quest_plus.intensity_unit;
    analysis::QuestPlusPosterior posterior;
    posterior.participant_label = participant_label;
    posterior.track = spec.name;
    posterior.method = experiment.procedure;
    posterior.trials = q->trial_count();
    const std::vector<ParameterSummary> summary = q->summary();
    for (std::size_t p = 0; p < spec.parameters.size(); ++p) {
      analysis::MarginalPosterior marginal;
      marginal.parameter = spec.parameters[p].name;
      marginal.unit = parameter_unit(spec, spec.parameters[p], intensity_unit_label(intensity_unit));
      marginal.values = spec.parameters[p].values;
      marginal.probabilities = q->marginal(p);
      marginal.mode = summary.at(p).mode;
      marginal.mean = summary.at(p).mean;
      marginal.sd = summary.at(p).sd;
      posterior.marginals.push_back(std::move(marginal));
    }
    tracks.push_back(std::move(posterior));
  }
  return tracks;
}

std::vector<analysis::QuestPlusPosterior> rebuild_quest_plus_posteriors(const analysis::LoadedData& data,
                                                                        std::vector<std::string>& notes) {
  std::vector<analysis::QuestPlusPosterior> all;
  for (const analysis::LoadedSession& session : data.sessions) {
    if (!runs_quest_plus(session)) continue;
    try {
      const ReplayedSession replayed = replay_stored_session(session);
      const auto* adaptive = dynamic_cast<const AdaptiveProcedure*>(replayed.procedure.get());
      if (!adaptive) throw std::logic_error("its stored design is not an adaptive procedure");
      for (auto& track : quest_plus_posteriors_of(*adaptive, replayed.experiment, session.label))
        all.push_back(std::move(track));
    } catch (const std::exception& error) {
      // Any failure of the rebuild (a moved scene file, an unreadable design) costs this
      // session's posterior figure, not the rest of the report.
      notes.push_back("session " + session.label + ": the QUEST+ posterior was not rebuilt: " + error.what());
    }
  }
  return all;
}

}  // namespace glarelab
