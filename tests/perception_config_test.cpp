// The [perception] table and the per-condition perception column: every stage off by default,
// strict keys and ranges with their place in the file, the column's stage lists, and the round
// trip through the resolved configuration.
#include <gtest/gtest.h>

#include <string>

#include "protocols/experiment.h"

namespace glarelab {
namespace {

// The [perception] table (if any) starts at line 8.
std::string experiment_with(const std::string& perception_table, const std::string& second_row) {
  return "[experiment]\nname = \"p\"\n[scenes]\na = { file = \"a.exr\" }\n[procedure]\ntype = \"forced_choice\"\n\n" +
         perception_table + "\n[[conditions.rows]]\nname = \"one\"\nscene_a = \"a\"\nscene_b = \"a\"\n" +
         "[[conditions.rows]]\nname = \"two\"\nscene_a = \"a\"\nscene_b = \"a\"\n" + second_row + "\n";
}

std::string refusal(const std::string& text) {
  try {
    parse_experiment_text(text, "p.toml", "/tmp");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

TEST(PerceptionConfig, EveryStageIsOffWithoutATable) {
  const Experiment e = parse_experiment_text(experiment_with("", ""), "p.toml", "/tmp");
  EXPECT_FALSE(any_perception_stage(e.perception));
  EXPECT_FALSE(any_perception_stage(perception_for(e.perception, e.conditions[1])));
  EXPECT_EQ(perception_stages_label(e.perception), "none");
  // The parameters are the stages' own defaults.
  EXPECT_EQ(e.perception.tone_mapping_settings.curve, ToneCurve::aces_narkowicz);
  EXPECT_EQ(e.perception.adaptation_time_constants.rod_time_constant_s, 0.4);
  EXPECT_EQ(e.perception.acuity_settings.max_sigma_px, 1.0);
}

TEST(PerceptionConfig, TableSwitchesParametersAndTheRowColumn) {
  const Experiment e = parse_experiment_text(
      experiment_with("[perception]\nadaptation = true\ntone_mapping = true\ntone_curve = \"aces_hill\"\n"
                      "scotopic_form = \"spencer_desaturation\"\nspencer_saturation_reduction = 0.5\n"
                      "max_sigma_px = 2.5\nacuity_sigma = \"luidolt_linear\"\nrod_time_constant_s = 0.8\n"
                      "gaze_sigma_frame_widths = 0.25\nresampled_size_px = 64\ntop_level_size_px = 8",
                      "perception = \"acuity+scotopic\""),
      "p.toml", "/tmp");
  const PerceptionSettings one = perception_for(e.perception, e.conditions[0]);
  EXPECT_TRUE(one.adaptation);
  EXPECT_FALSE(one.acuity);
  EXPECT_TRUE(one.tone_mapping);
  EXPECT_FALSE(one.scotopic);
  EXPECT_EQ(perception_stages_label(one), "adaptation+tone_mapping");
  const PerceptionSettings two = perception_for(e.perception, e.conditions[1]);
  EXPECT_FALSE(two.adaptation);
  EXPECT_TRUE(two.acuity);
  EXPECT_FALSE(two.tone_mapping);
  EXPECT_TRUE(two.scotopic);
  // The parameters are the table's in every row.
  EXPECT_EQ(two.tone_mapping_settings.curve, ToneCurve::aces_hill);
  EXPECT_EQ(two.scotopic_settings.form, ScotopicForm::spencer_desaturation);
  EXPECT_EQ(two.scotopic_settings.spencer_saturation_reduction, 0.5);
  EXPECT_EQ(two.acuity_settings.max_sigma_px, 2.5);
  EXPECT_EQ(two.acuity_settings.sigma_form, AcuitySigmaForm::luidolt_linear);
  EXPECT_EQ(two.adaptation_time_constants.rod_time_constant_s, 0.8);
  EXPECT_EQ(two.adaptation_weighting.gaze_sigma_frame_widths, 0.25);
  EXPECT_EQ(two.adaptation_weighting.resampled_size_px, 64);
  EXPECT_EQ(two.adaptation_weighting.top_level_size_px, 8);
}

TEST(PerceptionConfig, ColumnSpellings) {
  const auto row = [](const std::string& value) {
    ConditionRow r;
    r.fields = {{"name", "r"}, {"perception", value}};
    return r;
  };
  const PerceptionSettings off = perception_defaults();
  EXPECT_EQ(perception_stages_label(perception_for(off, row("all"))), "adaptation+acuity+tone_mapping+scotopic");
  EXPECT_EQ(perception_stages_label(perception_for(off, row("none"))), "none");
  EXPECT_EQ(perception_stages_label(perception_for(off, row("scotopic+adaptation"))), "adaptation+scotopic");
  PerceptionSettings on = perception_defaults();
  on.acuity = true;
  EXPECT_EQ(perception_stages_label(perception_for(on, row(""))), "acuity");  // empty: the table's
  EXPECT_EQ(perception_stages_label(perception_for(on, row("none"))), "none");
}

TEST(PerceptionConfig, RoundTripsThroughTheResolvedConfiguration) {
  const Experiment e = parse_experiment_text(
      experiment_with("[perception]\nacuity = true\nscotopic = true\ntone_curve = \"none\"\nmiddle_grey = 0.2\n"
                      "acuity_second_pass = \"original_lightness\"\nreference_white_cd_m2 = 80\n"
                      "minimum_adapted_luminance_cd_m2 = 0.001\ncone_time_constant_s = 0.05\n"
                      "rod_half_sensitivity_cd_m2 = 0.03\naces_pre_exposure = 0.7",
                      "perception = \"adaptation\""),
      "p.toml", "/tmp");
  const std::string resolved = resolved_config_toml(e);
  const Experiment reread = parse_experiment_text(resolved, "<stored config>", "/");
  EXPECT_EQ(resolved_config_toml(reread), resolved);
  const PerceptionSettings& p = reread.perception;
  EXPECT_FALSE(p.adaptation);
  EXPECT_TRUE(p.acuity);
  EXPECT_FALSE(p.tone_mapping);
  EXPECT_TRUE(p.scotopic);
  EXPECT_EQ(p.tone_mapping_settings.curve, ToneCurve::none);
  EXPECT_EQ(p.tone_mapping_settings.middle_grey, 0.2);
  EXPECT_EQ(p.tone_mapping_settings.aces_pre_exposure, 0.7);
  EXPECT_EQ(p.tone_mapping_settings.minimum_adapted_luminance_cd_m2, 0.001);
  EXPECT_EQ(p.acuity_settings.second_pass, SecondPassSigma::original_lightness);
  EXPECT_EQ(p.acuity_settings.reference_white_cd_m2, 80.0);
  EXPECT_EQ(p.adaptation_time_constants.cone_time_constant_s, 0.05);
  EXPECT_EQ(p.adaptation_time_constants.rod_half_sensitivity_cd_m2, 0.03);
  EXPECT_EQ(perception_stages_label(perception_for(p, reread.conditions[1])), "adaptation");
  // An experiment without the table stores every stage off and reads back so.
  const Experiment plain = parse_experiment_text(experiment_with("", ""), "p.toml", "/tmp");
  const Experiment plain_reread = parse_experiment_text(resolved_config_toml(plain), "<stored config>", "/");
  EXPECT_FALSE(any_perception_stage(plain_reread.perception));
}

TEST(PerceptionConfig, RefusalsNameFileLineColumnAndKey) {
  // Line 8 is the table's header, its first key on line 9.
  std::string message = refusal(experiment_with("[perception]\ntone_curv = \"aces_hill\"", ""));
  EXPECT_NE(message.find("p.toml:9:1"), std::string::npos) << message;
  EXPECT_NE(message.find("perception.tone_curv"), std::string::npos) << message;
  message = refusal(experiment_with("[perception]\ntone_curve = \"aces\"", ""));
  EXPECT_NE(message.find("p.toml:9:14"), std::string::npos) << message;
  EXPECT_NE(message.find("perception.tone_curve"), std::string::npos) << message;
  EXPECT_NE(message.find("\"aces_narkowicz\", \"aces_hill\", \"none\""), std::string::npos) << message;
  message = refusal(experiment_with("[perception]\nacuity = true\nmax_sigma_px = 20", ""));
  EXPECT_NE(message.find("p.toml:10:16"), std::string::npos) << message;
  EXPECT_NE(message.find("perception.max_sigma_px"), std::string::npos) << message;
  EXPECT_NE(message.find("(0, 10]"), std::string::npos) << message;
  message = refusal(experiment_with("[perception]\nadaptation = \"yes\"", ""));
  EXPECT_NE(message.find("perception.adaptation"), std::string::npos) << message;
  message = refusal(experiment_with("[perception]\nrod_time_constant_s = -1", ""));
  EXPECT_NE(message.find("perception.rod_time_constant_s"), std::string::npos) << message;
  message = refusal(experiment_with("[perception]\nresampled_size_px = 128\ntop_level_size_px = 48", ""));
  EXPECT_NE(message.find("perception.top_level_size_px"), std::string::npos) << message;
  message = refusal(experiment_with("[perception]\nspencer_saturation_reduction = 1.5", ""));
  EXPECT_NE(message.find("perception.spencer_saturation_reduction"), std::string::npos) << message;
  message = refusal(experiment_with("[perception]\nscotopic_form = \"purple\"", ""));
  EXPECT_NE(message.find("perception.scotopic_form"), std::string::npos) << message;
  message = refusal(experiment_with("[perceptoin]\nacuity = true", ""));
  EXPECT_NE(message.find("perceptoin"), std::string::npos) << message;
}

TEST(PerceptionConfig, ColumnRefusalsNameTheRow) {
  std::string message = refusal(experiment_with("", "perception = \"acuity+glow\""));
  EXPECT_NE(message.find("condition 'two' perception"), std::string::npos) << message;
  EXPECT_NE(message.find("unknown perception stage 'glow'"), std::string::npos) << message;
  EXPECT_NE(message.find("p.toml:"), std::string::npos) << message;
  message = refusal(experiment_with("", "perception = \"acuity+acuity\""));
  EXPECT_NE(message.find("named twice"), std::string::npos) << message;
  message = refusal(experiment_with("", "perception = \"acuity+\""));
  EXPECT_NE(message.find("unknown perception stage ''"), std::string::npos) << message;
  message = refusal(experiment_with("", "perception = \"glare\""));
  EXPECT_NE(message.find("unknown perception stage 'glare'"), std::string::npos) << message;
}

}  // namespace
}  // namespace glarelab
