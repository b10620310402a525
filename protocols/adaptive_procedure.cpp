#include "protocols/adaptive_procedure.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "core/number_text.h"
#include "protocols/block_design.h"
#include "protocols/forced_choice.h"
#include "protocols/glare_config.h"
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

// A condition cell as a number (the whole text, as from_chars reads it).
double cell_number(const ConditionRow& row, const std::string& column) {
  const std::string* text = row.find(column);
  if (text == nullptr)
    throw std::invalid_argument("condition '" + row.name() + "' has no column '" + column + "'");
  double value = 0.0;
  const char* end = text->data() + text->size();
  const auto [ptr, ec] = std::from_chars(text->data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value))
    throw std::invalid_argument("condition '" + row.name() + "' column '" + column + "': '" + *text +
                                "' is not a number");
  return value;
}

// The glare gain of a row: its glare_gain column (a number >= 0), 1 without it.
double glare_gain_of(const ConditionRow& row) {
  if (row.find("glare_gain") == nullptr) return 1.0;
  const double gain = cell_number(row, "glare_gain");
  if (gain < 0.0) throw std::invalid_argument("condition '" + row.name() + "' column 'glare_gain' must be >= 0");
  return gain;
}

// The shortest text that reads back to exactly `value` (posterior summaries are logged in full).
std::string exact_text(double value) {
  char buffer[64];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, end.ptr);
}

}  // namespace

double quest_plus_luminance_cd_m2(const std::string& intensity_unit, double intensity) {
  if (intensity_unit == "db_cd_m2") return std::pow(10.0, intensity / 20.0);
  if (intensity_unit == "log10_cd_m2") return std::pow(10.0, intensity);
  throw std::invalid_argument("unknown intensity unit '" + intensity_unit + "'");
}

QuestPlusTrackGrid quest_plus_track_grid(const Experiment& experiment, const AdaptiveTrackSpec& track) {
  const QuestPlusTrackSpec& qp = track.quest_plus;
  QuestPlusTrackGrid grid;
  grid.spec = qp.spec;
  std::vector<std::size_t> rows;
  if (qp.conditions.empty()) {
    rows.push_back(row_named(experiment, track.condition));
  } else {
    for (const std::string& name : qp.conditions) rows.push_back(row_named(experiment, name));
  }
  const std::size_t columns = qp.stimulus_columns.size();
  if (columns == 0) {
    grid.rows = {rows.front()};
    return grid;
  }
  // Each column's grid: its distinct values over the rows, in row order.
  std::vector<std::vector<double>> row_values(rows.size());
  for (std::size_t c = 0; c < columns; ++c) {
    std::vector<double>& values = grid.spec.stimulus.at(c + 1).values;
    values.clear();
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const double v = cell_number(experiment.conditions[rows[r]], qp.stimulus_columns[c]);
      row_values[r].push_back(v);
      if (std::find(values.begin(), values.end(), v) == values.end()) values.push_back(v);
    }
  }
  std::size_t points = 1;
  for (std::size_t c = 0; c < columns; ++c) points *= grid.spec.stimulus[c + 1].values.size();
  constexpr std::size_t kUnset = static_cast<std::size_t>(-1);
  grid.rows.assign(points, kUnset);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    std::size_t point = 0;
    for (std::size_t c = 0; c < columns; ++c) {
      const std::vector<double>& values = grid.spec.stimulus[c + 1].values;
      point = point * values.size() +
              static_cast<std::size_t>(std::find(values.begin(), values.end(), row_values[r][c]) - values.begin());
    }
    if (grid.rows[point] != kUnset)
      throw std::invalid_argument("conditions '" + experiment.conditions[grid.rows[point]].name() + "' and '" +
                                  experiment.conditions[rows[r]].name() + "' have the same stimulus_columns values");
    grid.rows[point] = rows[r];
  }
  for (std::size_t point = 0; point < points; ++point) {
    if (grid.rows[point] != kUnset) continue;
    std::string missing;
    std::size_t rest = point;
    std::vector<std::string> parts(columns);
    for (std::size_t c = columns; c-- > 0;) {
      const std::vector<double>& values = grid.spec.stimulus[c + 1].values;
      parts[c] = qp.stimulus_columns[c] + " = " + number_text(values[rest % values.size()]);
      rest /= values.size();
    }
    for (const std::string& part : parts) missing += (missing.empty() ? "" : ", ") + part;
    throw std::invalid_argument("the rows of conditions must hold every combination of stimulus_columns values; none has " +
                                missing);
  }
  validate_quest_plus_spec(grid.spec);
  return grid;
}

double AdaptiveProcedure::Track::next_luminance_cd_m2() const {
  // QUEST's scale is log10 cd/m2 (Watson & Pelli 1983 work on log intensity); QUEST+'s intensity
  // is the first stimulus dimension, in its track's unit.
  if (staircase) return staircase->next_intensity();
  if (quest) return std::pow(10.0, quest->next_intensity());
  return quest_plus_luminance_cd_m2(intensity_unit, quest_plus->next_stimulus().front());
}

std::size_t AdaptiveProcedure::Track::next_row() const {
  if (!quest_plus || quest_plus_rows.size() == 1) return row;
  return quest_plus_rows[quest_plus->next_stimulus_index() % quest_plus_rows.size()];
}

AdaptiveProcedure::AdaptiveProcedure(const Experiment& experiment, const std::map<std::string, double>& source_peak_cd_m2)
    : experiment_(experiment), peak_cd_m2_(source_peak_cd_m2) {
  if (experiment.adaptive.tracks.empty()) throw std::invalid_argument("adaptive procedure: no staircase");
  for (const AdaptiveTrackSpec& spec : experiment.adaptive.tracks) {
    Track track;
    track.row = row_named(experiment, spec.condition);
    if (experiment.procedure == "staircase") {
      track.name = spec.staircase.name;
      track.staircase.emplace(spec.staircase);
    } else if (experiment.procedure == "quest") {
      track.name = spec.quest.name;
      track.quest.emplace(spec.quest);
    } else {
      track.name = spec.quest_plus.spec.name;
      QuestPlusTrackGrid grid = quest_plus_track_grid(experiment, spec);
      track.quest_plus.emplace(std::move(grid.spec));
      track.quest_plus_rows = std::move(grid.rows);
      track.row = track.quest_plus_rows.front();
      track.intensity_unit = spec.quest_plus.intensity_unit;
    }
    std::vector<std::size_t> rows = track.quest_plus_rows;
    if (rows.empty()) rows.push_back(track.row);
    for (std::size_t shown : rows) {
      const ConditionRow& shown_row = experiment.conditions[shown];
      for (const char* column : {"reference", "comparison"}) {
        const std::string* scene = shown_row.find(column);
        if (scene == nullptr)
          throw std::invalid_argument("adaptive procedure: condition '" + shown_row.name() + "' lacks " + column);
        peak_of(peak_cd_m2_, *scene);
      }
    }
    tracks_.push_back(std::move(track));
  }
  const DesignSpec& design = experiment.design;
  if (design.blocks.empty()) {
    // One group of every track: the order the procedure always had.
    TrackGroup all;
    for (std::size_t i = 0; i < tracks_.size(); ++i) all.tracks.push_back(i);
    all.seed = experiment.seed;
    groups_.push_back(std::move(all));
    return;
  }
  int position = 0;
  for (const int index : block_sequence(design, experiment.seed)) {
    const BlockSpec& block = design.blocks[static_cast<std::size_t>(index)];
    TrackGroup group;
    const std::vector<std::size_t> rows = block_rows(experiment, block);
    for (std::size_t i = 0; i < tracks_.size(); ++i)
      if (std::find(rows.begin(), rows.end(), tracks_[i].row) != rows.end()) group.tracks.push_back(i);
    group.seed = block_trial_seed(design, experiment.seed, index);
    group.shuffled = block.trial_order == TrialOrder::random;
    // A block without tracks has nothing to show (its rows have no track): it is passed over.
    if (group.tracks.empty()) continue;
    group.placement = BlockPlacement{position++, block.name, block.instructions, block.question};
    groups_.push_back(std::move(group));
  }
}

bool AdaptiveProcedure::finished() const {
  return std::all_of(tracks_.begin(), tracks_.end(), [](const Track& t) { return t.finished(); });
}

int AdaptiveProcedure::planned_trials() const {
  int total = 0;
  for (const Track& t : tracks_) {
    if (t.staircase) total += t.staircase->spec().n_trials;
    else if (t.quest) total += t.quest->spec().n_trials;
    // QUEST+ stops at max_trials, or (with stop_sd) possibly after min_trials.
    else total += t.quest_plus->spec().stop_sd ? t.quest_plus->spec().min_trials : t.quest_plus->spec().max_trials;
  }
  return total;
}

const Staircase* AdaptiveProcedure::staircase(std::size_t track) const {
  return tracks_.at(track).staircase ? &*tracks_.at(track).staircase : nullptr;
}
const Quest* AdaptiveProcedure::quest(std::size_t track) const {
  return tracks_.at(track).quest ? &*tracks_.at(track).quest : nullptr;
}
const QuestPlus* AdaptiveProcedure::quest_plus(std::size_t track) const {
  return tracks_.at(track).quest_plus ? &*tracks_.at(track).quest_plus : nullptr;
}

bool AdaptiveProcedure::group_finished(const TrackGroup& group) const {
  return std::all_of(group.tracks.begin(), group.tracks.end(), [&](std::size_t t) { return tracks_[t].finished(); });
}

// The same pass scheme as InterleavedStaircases::next (MultiStairHandler._startNewPass), within
// the group (block) running now; the next group starts when all of its tracks are finished.
std::size_t AdaptiveProcedure::choose_track() {
  while (group_ < groups_.size()) {
    TrackGroup& group = groups_[group_];
    if (group_finished(group)) {
      ++group_;
      continue;
    }
    if (group.pass_remaining.empty()) {
      group.pass_remaining = group.tracks;
      if (group.shuffled)
        shuffle_in_place(group.pass_remaining, CounterRandom(group.seed, RandomStream::staircase),
                         group.pass * group.tracks.size());
      ++group.pass;
    }
    const std::size_t candidate = group.pass_remaining.front();
    group.pass_remaining.erase(group.pass_remaining.begin());
    if (!tracks_[candidate].finished()) return candidate;
  }
  throw std::logic_error("adaptive procedure: all staircases are finished");
}

bool AdaptiveProcedure::show_row_on_its_tracks_next_trial(std::size_t row) {
  // A track of one row shows it on its first trial, as the session does: nothing to change.
  if (std::any_of(tracks_.begin(), tracks_.end(),
                  [&](const Track& track) { return track.row == row && track.quest_plus_rows.size() <= 1; }))
    return true;
  const bool shown = std::any_of(tracks_.begin(), tracks_.end(), [&](const Track& track) {
    return std::find(track.quest_plus_rows.begin(), track.quest_plus_rows.end(), row) != track.quest_plus_rows.end();
  });
  if (shown) preview_row_ = row;
  return shown;
}

TrialPlan AdaptiveProcedure::next_trial() {
  if (!current_) current_ = choose_track();
  const Track& track = tracks_[*current_];
  std::size_t shown_row = track.next_row();
  preview_note_.clear();
  if (preview_row_ && shown_row != *preview_row_ &&
      std::find(track.quest_plus_rows.begin(), track.quest_plus_rows.end(), *preview_row_) != track.quest_plus_rows.end()) {
    preview_note_ = "track '" + track.name + "' chose condition '" + experiment_.conditions[shown_row].name() +
                   "' for this trial (QUEST+ picks the row with the intensity); shown with condition '" +
                   experiment_.conditions[*preview_row_].name() + "' in its place at the intensity the track chose";
    shown_row = *preview_row_;
  }
  const ConditionRow& row = experiment_.conditions[shown_row];
  const std::string& reference = *row.find("reference");
  const std::string& comparison = *row.find("comparison");
  const double intensity_cd_m2 = track.next_luminance_cd_m2();
  const ForcedChoiceSpec& spec = experiment_.forced_choice;
  const std::vector<std::string>& positions = forced_choice_positions(spec);

  TrialPlan plan;
  plan.trial_index = trials_done_;
  // QUEST+ and Psi trials are stored as procedure "quest" (the trials table's CHECK list); the
  // condition record names the method.
  plan.procedure = track.quest_plus ? "quest" : experiment_.procedure;
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
  const AdaptiveSpec& adaptive = experiment_.adaptive;
  const GlareMode glare = glare_mode_for(experiment_.glare, row);
  if (adaptive.glare_reference_only) {
    // Spencer 1995, section 4: the glare image against a plain disc; the glare follows the
    // reference to whichever side it was drawn.
    plan.position_glare = comparison_left ? std::vector<std::string>{"control", to_string(glare)}
                                          : std::vector<std::string>{to_string(glare), "control"};
    plan.glare_keeps_peak = adaptive.glare_keeps_peak;
  }
  plan.scene_scale = comparison_left ? std::vector<double>{comparison_scale, 1.0}
                                     : std::vector<double>{1.0, comparison_scale};
  plan.source_luminance_cd_m2 = comparison_left ? std::vector<double>{intensity_cd_m2, reference_cd_m2}
                                                : std::vector<double>{reference_cd_m2, intensity_cd_m2};
  plan.allowed_responses = spec.responses;
  const std::size_t comparison_position = comparison_left ? 0 : 1;
  plan.comparison_positions = {static_cast<int>(comparison_position)};
  const bool pse = adaptive.response_rule == AdaptiveResponseRule::pse;
  const double reference_gain = pse && glare != GlareMode::control ? glare_gain_of(row) : 0.0;
  if (pse) {
    // No answer is right: the observer says which looks brighter.
    plan.appearance_judgement = true;
    const double comparison_gain = adaptive.glare_reference_only ? 0.0 : reference_gain;
    plan.position_glare_gain = comparison_left ? std::vector<double>{comparison_gain, reference_gain}
                                               : std::vector<double>{reference_gain, comparison_gain};
  } else if (std::abs(intensity_cd_m2 - reference_cd_m2) <= 1e-9 * std::max(intensity_cd_m2, reference_cd_m2)) {
    // Relative 1e-9: the same luminance reached by different step paths is still equal.
    plan.correct_response = spec.responses.size() == 3 ? spec.responses[2] : spec.responses[comparison_position];
  } else {
    plan.correct_response = spec.responses[intensity_cd_m2 > reference_cd_m2 ? comparison_position
                                                                             : 1 - comparison_position];
  }
  plan.intensity = intensity_cd_m2;
  plan.question = spec.question;
  plan.stimulus_frames = spec.stimulus_frames;
  const TrackGroup& group = groups_[group_];
  if (!group.placement.block_name.empty()) {
    BlockPlacement placement = group.placement;
    if (group.trials_done > 0) placement.screen_text.clear();  // the block's instructions: before its first trial
    apply_block_placement(placement, false, plan);
  }

  JsonObjectWriter json;
  for (const auto& [column, value] : row.fields) json.add(column, value);
  json.add(positions[0], plan.scenes[0]).add(positions[1], plan.scenes[1]);
  json.add("staircase", track.name);
  if (!group.placement.block_name.empty()) json.add("block_name", group.placement.block_name);
  for (std::size_t p = 0; p < plan.position_glare.size(); ++p) json.add(positions[p] + "_glare", plan.position_glare[p]);
  if (plan.glare_keeps_peak) json.add("glare_keeps_peak", "true");
  if (pse) {
    // What the PSE analysis needs (analysis/pse_analysis.h): which side the comparison was on,
    // the reference's luminance and the display's peak (PSEs are reported as fractions of it).
    json.add("response_rule", "pse");
    json.add("comparison_position", positions[comparison_position]);
    json.add("comparison_response", spec.responses[comparison_position]);
    json.add("reference_response", spec.responses[1 - comparison_position]);
    json.add("reference_cd_m2", exact_text(reference_cd_m2));
    json.add("reference_glare_gain", exact_text(reference_gain));
    json.add("display_peak_cd_m2", exact_text(experiment_.display.peak_luminance_cd_m2));
  }
  if (track.quest_plus) {
    // The posterior the stimulus was chosen from (after the track's earlier trials): per
    // parameter its value at the joint mode, marginal mean and SD; thresholds in intensity_unit.
    const QuestPlus& q = *track.quest_plus;
    json.add("method", experiment_.procedure);
    json.add("intensity_unit", track.intensity_unit);
    json.add("intensity", exact_text(q.next_stimulus().front()));
    json.add("track_trials_done", number_text(q.trial_count()));
    json.add("expected_entropy_nats", exact_text(q.next_expected_entropy()));
    for (const ParameterSummary& p : q.summary()) {
      json.add("posterior_" + p.name + "_mode", exact_text(p.mode));
      json.add("posterior_" + p.name + "_mean", exact_text(p.mean));
      json.add("posterior_" + p.name + "_sd", exact_text(p.sd));
    }
  }
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
    ++groups_[group_].trials_done;
    return outcome;
  }
  const auto& allowed = plan.allowed_responses;
  if (std::find(allowed.begin(), allowed.end(), response.value) == allowed.end()) return outcome;  // not an answer
  Track& track = tracks_[*current_];
  if (plan.appearance_judgement) {
    // PSE rule: the step follows what looked brighter; no answer is scored.
    const std::vector<std::string>& responses = experiment_.forced_choice.responses;
    const auto comparison_position = static_cast<std::size_t>(plan.comparison_positions.at(0));
    bool step_down = false;
    if (response.value == responses[comparison_position]) {
      step_down = true;
    } else if (response.value == responses[1 - comparison_position]) {
      step_down = false;
    } else if (track.last_pse_step_down) {
      // "Neither": the track has crossed into the band the observer cannot tell apart; turn back.
      step_down = !*track.last_pse_step_down;
    } else {
      const StaircaseSpec& s = track.staircase->spec();
      step_down = track.staircase->next_intensity() > 0.5 * (*s.min_value + *s.max_value);
    }
    track.last_pse_step_down = step_down;
    outcome.reversal = track.staircase->add_response(step_down) ? 1 : 0;
    current_.reset();
    ++trials_done_;
    ++groups_[group_].trials_done;
    return outcome;
  }
  const bool correct = response.value == plan.correct_response;
  outcome.correct = correct ? 1 : 0;
  if (track.staircase) {
    outcome.reversal = track.staircase->add_response(correct) ? 1 : 0;
  } else if (track.quest_plus) {
    track.quest_plus->add_response(correct);
    outcome.reversal = 0;  // no reversals
  } else {
    track.quest->add_response(correct);
    outcome.reversal = 0;  // QUEST has no reversals
  }
  current_.reset();
  ++trials_done_;
  ++groups_[group_].trials_done;
  return outcome;
}

}  // namespace glarelab
