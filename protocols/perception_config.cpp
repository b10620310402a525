// [perception] table and the "perception" condition column. Read through TableReader so a
// misspelt key stops the run (protocols/toml_table_reader.h). The ranges are those the stages
// themselves accept (stimuli/perception/*: validate_*), checked here so a wrong value is reported
// at its place in the file before a session starts.
#include "protocols/perception_config.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "core/number_text.h"
#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {
namespace {

// A number in (0, maximum].
double read_positive_at_most(TableReader& reader, std::string_view key, double fallback, double maximum) {
  const double value = reader.positive_number(key, fallback);
  if (value > maximum)
    reader.fail(key, "must be in (0, " + number_text(maximum) + "], found " + number_text(value));
  return value;
}

// An experiment-file spelling through core's parser, whose message names the accepted values.
template <typename Enum>
Enum read_spelling(TableReader& reader, std::string_view key, Enum fallback,
                   const std::function<Enum(const std::string&)>& parse) {
  const std::optional<std::string> value = reader.string(key);
  if (!value) return fallback;
  try {
    return parse(*value);
  } catch (const std::invalid_argument& error) {
    reader.fail(key, error.what());
  }
}

struct StageSwitch {
  const char* name;
  bool PerceptionSettings::*on;
};

// Fig. 6.1's order (the glare, between adaptation and acuity, is the [glare] table's).
constexpr StageSwitch kStages[] = {{"adaptation", &PerceptionSettings::adaptation},
                                   {"acuity", &PerceptionSettings::acuity},
                                   {"tone_mapping", &PerceptionSettings::tone_mapping},
                                   {"scotopic", &PerceptionSettings::scotopic}};

}  // namespace

PerceptionSettings perception_defaults() {
  PerceptionSettings settings;
  for (const StageSwitch& stage : kStages) settings.*stage.on = false;
  return settings;
}

PerceptionSettings read_perception_section(TableReader& top) {
  PerceptionSettings settings = perception_defaults();
  const toml::table* table = top.table("perception");
  if (table == nullptr) return settings;
  TableReader reader(*table, "perception", top.file());
  for (const StageSwitch& stage : kStages) settings.*stage.on = reader.boolean(stage.name).value_or(false);

  // Section 5.1: the gaze-weighted adaptation luminance and Eqs. 5.2-5.4's time constants.
  AdaptationWeighting& weighting = settings.adaptation_weighting;
  weighting.gaze_sigma_frame_widths =
      read_positive_at_most(reader, "gaze_sigma_frame_widths", weighting.gaze_sigma_frame_widths, 10.0);
  weighting.resampled_size_px =
      static_cast<int>(reader.integer_in_range("resampled_size_px", weighting.resampled_size_px, 1, 4096));
  weighting.top_level_size_px = static_cast<int>(
      reader.integer_in_range("top_level_size_px", weighting.top_level_size_px, 1, weighting.resampled_size_px));
  const auto levels = static_cast<unsigned>(weighting.resampled_size_px / weighting.top_level_size_px);
  if (weighting.resampled_size_px % weighting.top_level_size_px != 0 || !std::has_single_bit(levels))
    reader.fail("top_level_size_px", "resampled_size_px / top_level_size_px must be a power of two (a Gaussian pyramid "
                                     "halves each level), found " + std::to_string(weighting.resampled_size_px) +
                                         " / " + std::to_string(weighting.top_level_size_px));
  AdaptationTimeConstants& time = settings.adaptation_time_constants;
  time.rod_time_constant_s = read_positive_at_most(reader, "rod_time_constant_s", time.rod_time_constant_s, 3600.0);
  time.cone_time_constant_s = read_positive_at_most(reader, "cone_time_constant_s", time.cone_time_constant_s, 3600.0);
  time.rod_half_sensitivity_cd_m2 =
      read_positive_at_most(reader, "rod_half_sensitivity_cd_m2", time.rod_half_sensitivity_cd_m2, 1e4);

  // Section 5.3: the acuity blur.
  AcuitySettings& acuity = settings.acuity_settings;
  acuity.sigma_form = read_spelling<AcuitySigmaForm>(reader, "acuity_sigma", acuity.sigma_form, parse_acuity_sigma_form);
  acuity.second_pass =
      read_spelling<SecondPassSigma>(reader, "acuity_second_pass", acuity.second_pass, parse_second_pass_sigma);
  acuity.reference_white_cd_m2 =
      read_positive_at_most(reader, "reference_white_cd_m2", acuity.reference_white_cd_m2, 1e9);
  acuity.max_sigma_px = read_positive_at_most(reader, "max_sigma_px", acuity.max_sigma_px, 10.0);

  // Section 6.1: the tone curve with the adapted luminance as middle grey.
  ToneMappingSettings& tone = settings.tone_mapping_settings;
  tone.curve = read_spelling<ToneCurve>(reader, "tone_curve", tone.curve, parse_tone_curve);
  tone.middle_grey = read_positive_at_most(reader, "middle_grey", tone.middle_grey, 1.0);
  tone.aces_pre_exposure = read_positive_at_most(reader, "aces_pre_exposure", tone.aces_pre_exposure, 10.0);
  tone.minimum_adapted_luminance_cd_m2 =
      read_positive_at_most(reader, "minimum_adapted_luminance_cd_m2", tone.minimum_adapted_luminance_cd_m2, 1e9);

  // Section 5.4: the scotopic colour shift.
  ScotopicSettings& scotopic = settings.scotopic_settings;
  scotopic.form = read_spelling<ScotopicForm>(reader, "scotopic_form", scotopic.form, parse_scotopic_form);
  scotopic.spencer_saturation_reduction =
      reader.number_in_range("spencer_saturation_reduction", scotopic.spencer_saturation_reduction, 0.0, 1.0);
  reader.report_unused();
  return settings;
}

toml::table perception_section_toml(const PerceptionSettings& settings) {
  const AdaptationWeighting& weighting = settings.adaptation_weighting;
  const AdaptationTimeConstants& time = settings.adaptation_time_constants;
  const AcuitySettings& acuity = settings.acuity_settings;
  const ToneMappingSettings& tone = settings.tone_mapping_settings;
  return toml::table{{"adaptation", settings.adaptation},
                     {"acuity", settings.acuity},
                     {"tone_mapping", settings.tone_mapping},
                     {"scotopic", settings.scotopic},
                     {"gaze_sigma_frame_widths", weighting.gaze_sigma_frame_widths},
                     {"resampled_size_px", weighting.resampled_size_px},
                     {"top_level_size_px", weighting.top_level_size_px},
                     {"rod_time_constant_s", time.rod_time_constant_s},
                     {"cone_time_constant_s", time.cone_time_constant_s},
                     {"rod_half_sensitivity_cd_m2", time.rod_half_sensitivity_cd_m2},
                     {"acuity_sigma", to_string(acuity.sigma_form)},
                     {"acuity_second_pass", to_string(acuity.second_pass)},
                     {"reference_white_cd_m2", acuity.reference_white_cd_m2},
                     {"max_sigma_px", acuity.max_sigma_px},
                     {"tone_curve", to_string(tone.curve)},
                     {"middle_grey", tone.middle_grey},
                     {"aces_pre_exposure", tone.aces_pre_exposure},
                     {"minimum_adapted_luminance_cd_m2", tone.minimum_adapted_luminance_cd_m2},
                     {"scotopic_form", to_string(settings.scotopic_settings.form)},
                     {"spencer_saturation_reduction", settings.scotopic_settings.spencer_saturation_reduction}};
}

PerceptionSettings perception_for(const PerceptionSettings& settings, const ConditionRow& row) {
  const std::string* value = row.find("perception");
  if (value == nullptr || value->empty()) return settings;
  PerceptionSettings chosen = settings;
  const std::string key = "condition '" + row.name() + "' perception";
  const bool all = *value == "all";
  for (const StageSwitch& stage : kStages) chosen.*stage.on = all;
  if (all || *value == "none") return chosen;
  std::string listed;
  for (const StageSwitch& stage : kStages) listed += std::string(listed.empty() ? "'" : ", '") + stage.name + "'";
  std::size_t start = 0;
  while (start <= value->size()) {
    const std::size_t end = std::min(value->find('+', start), value->size());
    const std::string name = value->substr(start, end - start);
    const StageSwitch* found = nullptr;
    for (const StageSwitch& stage : kStages)
      if (name == stage.name) found = &stage;
    if (found == nullptr)
      throw ConfigError(row.where, key,
                        "unknown perception stage '" + name + "' in '" + *value + "' (write 'none', 'all' or stages " +
                            "joined by '+' from " + listed + ")");
    if (chosen.*found->on)
      throw ConfigError(row.where, key, "perception stage '" + name + "' named twice in '" + *value + "'");
    chosen.*found->on = true;
    start = end + 1;
  }
  return chosen;
}

bool any_perception_stage(const PerceptionSettings& settings) {
  for (const StageSwitch& stage : kStages)
    if (settings.*stage.on) return true;
  return false;
}

std::string perception_stages_label(const PerceptionSettings& settings) {
  std::string label;
  for (const StageSwitch& stage : kStages)
    if (settings.*stage.on) label += (label.empty() ? "" : "+") + std::string(stage.name);
  return label.empty() ? "none" : label;
}

}  // namespace glarelab
