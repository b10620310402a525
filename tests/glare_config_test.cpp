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

}  // namespace
}  // namespace glarelab
