// The [glare] table and the per-condition glare column: defaults, strict keys, modes per row, and
// the round trip through the resolved configuration.
#include <gtest/gtest.h>

#include "protocols/experiment.h"

namespace glarelab {
namespace {

std::string experiment_with(const std::string& glare_table, const std::string& second_row_glare) {
  return "[experiment]\nname = \"g\"\n[scenes]\na = { file = \"a.exr\" }\n[procedure]\ntype = \"forced_choice\"\n" +
         glare_table + "\n[[conditions.rows]]\nname = \"one\"\nscene_a = \"a\"\nscene_b = \"a\"\n" +
         "[[conditions.rows]]\nname = \"two\"\nscene_a = \"a\"\nscene_b = \"a\"\n" + second_row_glare + "\n";
}

TEST(GlareConfig, DefaultsToControlWithoutATable) {
  const Experiment e = parse_experiment_text(experiment_with("", ""), "g.toml", "/tmp");
  EXPECT_EQ(e.glare.mode, GlareMode::control);
  EXPECT_EQ(glare_mode_for(e.glare, e.conditions[1]), GlareMode::control);
}

TEST(GlareConfig, RowColumnOverridesTheTableModeAndRoundTrips) {
  const Experiment e = parse_experiment_text(
      experiment_with("[glare]\nmode = \"static\"\ngrid_px = 128\nstatic_time_s = 2.5\nskip_invisible = false",
                      "glare = \"dynamic\""),
      "g.toml", "/tmp");
  EXPECT_EQ(glare_mode_for(e.glare, e.conditions[0]), GlareMode::static_eye);
  EXPECT_EQ(glare_mode_for(e.glare, e.conditions[1]), GlareMode::dynamic);
  EXPECT_EQ(e.glare.grid_px, 128);
  const std::string resolved = resolved_config_toml(e);
  const Experiment reread = parse_experiment_text(resolved, "<stored config>", "/");
  EXPECT_EQ(resolved_config_toml(reread), resolved);
  EXPECT_EQ(reread.glare.mode, GlareMode::static_eye);
  EXPECT_EQ(reread.glare.grid_px, 128);
  EXPECT_EQ(reread.glare.static_time_s, 2.5);
  EXPECT_FALSE(reread.glare.skip_invisible);
  EXPECT_EQ(glare_mode_for(reread.glare, reread.conditions[1]), GlareMode::dynamic);
}

TEST(GlareConfig, BadValuesNameTheirKeyAndLine) {
  auto message = [](const std::string& text) {
    try {
      parse_experiment_text(text, "g.toml", "/tmp");
    } catch (const ConfigError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(experiment_with("[glare]\ngrid_pixels = 128", "")).find("glare.grid_pixels"), std::string::npos);
  EXPECT_NE(message(experiment_with("[glare]\ngrid_px = 127", "")).find("must be even"), std::string::npos);
  EXPECT_NE(message(experiment_with("[glare]\nmode = \"blurry\"", "")).find("g.toml:8"), std::string::npos);
  const std::string row = message(experiment_with("", "glare = \"wobbly\""));
  EXPECT_NE(row.find("unknown glare mode 'wobbly'"), std::string::npos) << row;
}

TEST(GlareConfig, BackendGazeWindowAndTrackerInputsAreReadStrictlyAndRoundTrip) {
  const Experiment defaults = parse_experiment_text(experiment_with("[glare]\nmode = \"dynamic\"", ""), "g.toml", "/tmp");
  EXPECT_EQ(spelling(defaults.glare.backend), "auto");
  EXPECT_EQ(defaults.glare.gaze_window_px, 0);
  EXPECT_EQ(spelling(defaults.glare.pupil_source), "tracker");
  EXPECT_EQ(spelling(defaults.glare.blink_source), "model");
  const Experiment e = parse_experiment_text(
      experiment_with("[glare]\nbackend = \"gl\"\ngrid_px = 512\ngaze_window_px = 256\npupil_source = \"model\"\n"
                      "blink_source = \"tracker\"",
                      ""),
      "g.toml", "/tmp");
  EXPECT_EQ(spelling(e.glare.backend), "gl");
  EXPECT_EQ(e.glare.gaze_window_px, 256);
  EXPECT_EQ(spelling(e.glare.pupil_source), "model");
  EXPECT_EQ(spelling(e.glare.blink_source), "tracker");
  const std::string resolved = resolved_config_toml(e);
  EXPECT_NE(resolved.find("backend = 'gl'"), std::string::npos) << resolved;
  const Experiment reread = parse_experiment_text(resolved, "<stored config>", "/");
  EXPECT_EQ(resolved_config_toml(reread), resolved);
  EXPECT_EQ(spelling(reread.glare.backend), "gl");
  EXPECT_EQ(reread.glare.gaze_window_px, 256);
  EXPECT_EQ(spelling(reread.glare.pupil_source), "model");
  EXPECT_EQ(spelling(reread.glare.blink_source), "tracker");
  EXPECT_FALSE(reread.glare.gaze_latency_compensation);  // off unless asked for
  const Experiment compensated = parse_experiment_text(
      experiment_with("[glare]\ngaze_window_px = 256\ngaze_latency_compensation = true", ""), "g.toml", "/tmp");
  EXPECT_TRUE(compensated.glare.gaze_latency_compensation);
  EXPECT_TRUE(parse_experiment_text(resolved_config_toml(compensated), "<stored config>", "/").glare.gaze_latency_compensation);
  EXPECT_THROW(parse_experiment_text(experiment_with("[glare]\ngaze_latency_compensation = 1", ""), "g.toml", "/tmp"),
               ConfigError);
}

TEST(GlareConfig, BadBackendWindowAndSourcesNameTheirKey) {
  auto message = [](const std::string& glare_table) {
    try {
      parse_experiment_text(experiment_with(glare_table, ""), "g.toml", "/tmp");
    } catch (const ConfigError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  const std::string cuda = message("[glare]\nbackend = \"cuda\"");
  EXPECT_NE(cuda.find("g.toml:8"), std::string::npos) << cuda;
  EXPECT_NE(cuda.find("glare.backend"), std::string::npos) << cuda;
  EXPECT_NE(cuda.find("unknown value 'cuda'"), std::string::npos) << cuda;
  // The GL FFT takes powers of two up to 4096: refused when read, not in the middle of a session.
  const std::string grid = message("[glare]\ngrid_px = 300\nbackend = \"gl\"");
  EXPECT_NE(grid.find("glare.backend"), std::string::npos) << grid;
  EXPECT_NE(grid.find("grid_px = 300"), std::string::npos) << grid;
  EXPECT_EQ(message("[glare]\ngrid_px = 300\nbackend = \"cpu\""), "no error");
  EXPECT_NE(message("[glare]\ngrid_px = 8192\nbackend = \"gl\"").find("glare.backend"), std::string::npos);
  for (const char* window : {"300", "8", "-256", "16384"}) {
    const std::string text = message(std::string("[glare]\ngaze_window_px = ") + window);
    EXPECT_NE(text.find("glare.gaze_window_px"), std::string::npos) << window << ": " << text;
    EXPECT_NE(text.find("power of two"), std::string::npos) << window << ": " << text;
  }
  EXPECT_NE(message("[glare]\npupil_source = \"camera\"").find("glare.pupil_source"), std::string::npos);
  EXPECT_NE(message("[glare]\nblink_source = \"eeg\"").find("glare.blink_source"), std::string::npos);
}

TEST(GlareConfig, ModelsRegimeSourceAndHandOverAreReadStrictlyAndRoundTrip) {
  const Experiment e = parse_experiment_text(
      experiment_with("[glare]\nmode = \"static\"\nmodel = \"hybrid\"\nregime = \"scotopic\"\nhybrid_far_field = \"cie\"\n"
                      "source = \"excess\"\nhybrid_handover_inner_deg = 0.05\nhybrid_handover_outer_deg = 0.1",
                      "glare_model = \"spencer\"\nglare_gain = \"2.5\""),
      "g.toml", "/tmp");
  EXPECT_EQ(e.glare.model, GlareModel::hybrid);
  EXPECT_EQ(e.glare.spencer_regime, SpencerRegime::scotopic);
  EXPECT_EQ(e.glare.hybrid_far_field, GlareModel::cie);
  EXPECT_EQ(spelling(e.glare.source), "excess");
  EXPECT_EQ(glare_model_for(e.glare, e.conditions[0]), GlareModel::hybrid);
  EXPECT_EQ(glare_model_for(e.glare, e.conditions[1]), GlareModel::spencer);
  EXPECT_EQ(glare_gain_for(e.conditions[0]), 1.0);
  EXPECT_EQ(glare_gain_for(e.conditions[1]), 2.5);
  const std::string resolved = resolved_config_toml(e);
  const Experiment reread = parse_experiment_text(resolved, "<stored config>", "/");
  EXPECT_EQ(resolved_config_toml(reread), resolved);
  EXPECT_EQ(reread.glare.model, GlareModel::hybrid);
  EXPECT_EQ(reread.glare.hybrid_handover_outer_deg, 0.1);
  EXPECT_EQ(glare_gain_for(reread.conditions[1]), 2.5);
  // Defaults: the human eye (the wave-optics near field at CIE 146's light, CIE beyond), the adaptive regime, all light.
  const Experiment plain = parse_experiment_text(experiment_with("", ""), "g.toml", "/tmp");
  EXPECT_EQ(plain.glare.model, GlareModel::human);
  EXPECT_EQ(plain.glare.spencer_regime, SpencerRegime::adaptive);
  EXPECT_EQ(spelling(plain.glare.source), "all");
}

TEST(GlareConfig, BadModelsGainsAndHandOversNameTheirKeyAndLine) {
  auto message = [](const std::string& text) {
    try {
      parse_experiment_text(text, "g.toml", "/tmp");
    } catch (const ConfigError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  const std::string model = message(experiment_with("[glare]\nmodel = \"vos\"", ""));
  EXPECT_NE(model.find("g.toml:8:9"), std::string::npos) << model;
  EXPECT_NE(model.find("glare.model"), std::string::npos) << model;
  EXPECT_NE(message(experiment_with("[glare]\nregime = \"twilight\"", "")).find("glare.regime"), std::string::npos);
  EXPECT_NE(message(experiment_with("[glare]\nsource = \"bright\"", "")).find("glare.source"), std::string::npos);
  // 256 px over 10 mm reaches 0.42 degrees, and 380 nm's copy of the PSF only 0.28.
  const std::string far = message(experiment_with(
      "[glare]\nmodel = \"hybrid\"\nhybrid_handover_inner_deg = 0.2\nhybrid_handover_outer_deg = 0.4", ""));
  EXPECT_NE(far.find("glare.hybrid_handover_outer_deg"), std::string::npos) << far;
  EXPECT_NE(far.find("beyond"), std::string::npos) << far;
  EXPECT_NE(message(experiment_with("[glare]\nhybrid_handover_outer_deg = 0.2", "")).find("both"), std::string::npos);
  const std::string row_model = message(experiment_with("", "glare_model = \"vos\""));
  EXPECT_NE(row_model.find("condition 'two' glare_model"), std::string::npos) << row_model;
  for (const char* gain : {"\"-1\"", "\"lots\"", "\"nan\"", "\"1e9\""}) {
    const std::string row_gain = message(experiment_with("", std::string("glare_gain = ") + gain));
    EXPECT_NE(row_gain.find("condition 'two' glare_gain"), std::string::npos) << row_gain;
  }
}

}  // namespace
}  // namespace glarelab
