// Experiment-file values that are typos rather than experiments: refused when the file is read,
// with file:line:column, the key, the bounds and the value as the user wrote it.
#include <gtest/gtest.h>

#include <string>

#include "core/number_text.h"
#include "protocols/experiment.h"
#include "experiment_error.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

// Line 2 holds the name and line 4 the one [display] key under test.
std::string experiment_text(const std::string& name_line, const std::string& display_line,
                            const std::string& procedure_line = "repetitions = 2") {
  return "[experiment]\n" + name_line + "\n"   // 1-2
         "[display]\n" + display_line + "\n"   // 3-4
         "[scenes]\n"                          // 5
         "a = { file = \"a.exr\" }\n"          // 6
         "b = { file = \"b.exr\" }\n"          // 7
         "[procedure]\n"                       // 8
         "type = \"forced_choice\"\n"          // 9
         + procedure_line + "\n"               // 10
         "[conditions]\n"                      // 11
         "rows = [{ name = \"ab\", scene_a = \"a\", scene_b = \"b\" }]\n";
}

std::string error_of(const std::string& path) { return test::experiment_error(path); }

TEST(NumberText, ShortestTextForWhatPeopleWriteSixDigitsForComputedValues) {
  EXPECT_EQ(number_text(0.25), "0.25");
  EXPECT_EQ(number_text(1e300), "1e+300");
  EXPECT_EQ(number_text(-1e-300), "-1e-300");  // printf's %f wrote "-0.000000"
  EXPECT_EQ(number_text(60.0), "60");
  EXPECT_EQ(number_text(123456789.0), "123456789");
  EXPECT_EQ(number_text(1e9), "1e+09");  // the shorter of the two forms
  EXPECT_EQ(number_text(1000.0 / 60.0), "16.6667");
  EXPECT_EQ(number_text(std::int64_t{9223372036854775807}), "9223372036854775807");
  EXPECT_EQ(number_text(std::uint64_t{18446744073709551615u}), "18446744073709551615");
}

TEST(ExperimentBounds, DisplayValuesBeyondAnyRealSetupAreRefusedWithTheirBounds) {
  test::ScratchDir dir;
  const auto check = [&](const std::string& display_line, const std::string& expected) {
    const std::string path = dir.write("exp.toml", experiment_text("name = \"x\"", display_line));
    EXPECT_EQ(error_of(path), path + expected) << display_line;
  };
  check("refresh_hz = 1e300", ":4:14: key 'display.refresh_hz': must be from 1 to 1000 Hz, found 1e+300");
  check("gamma = 1e300", ":4:9: key 'display.gamma': must be from 0.5 to 5, found 1e+300");
  check("viewing_distance_mm = 1e9",
        ":4:23: key 'display.viewing_distance_mm': must be from 10 to 1e+05 mm, found 1e+09");
  check("pixel_pitch_mm = -1e-300", ":4:18: key 'display.pixel_pitch_mm': must be from 0.001 to 100 mm, found -1e-300");
  check("width_px = 9223372036854775807",
        ":4:12: key 'display.width_px': must be from 1 to 16384, found 9223372036854775807");
  // The background is shown on the display: never above its peak (default 250 cd/m2).
  check("background_cd_m2 = 1e300",
        ":4:20: key 'display.background_cd_m2': must be from 0 to 250 cd/m2 (the display's peak), found 1e+300");
  const std::string scale = dir.write(
      "exp.toml", experiment_text("name = \"x\"", "").replace(
                      experiment_text("name = \"x\"", "").find("a = { file = \"a.exr\" }"), 22,
                      "a = { file = \"a.exr\", scale_cd_m2 = 1e-300 }"));
  EXPECT_EQ(error_of(scale), scale + ":6:37: key 'scenes.a.scale_cd_m2': must be from 1e-09 to 1e+09, found 1e-300");
}

TEST(ExperimentBounds, RepetitionsBeyondTenThousandAreATypo) {
  test::ScratchDir dir;
  const std::string path =
      dir.write("exp.toml", experiment_text("name = \"x\"", "", "repetitions = 9223372036854775807"));
  EXPECT_EQ(error_of(path),
            path + ":10:15: key 'procedure.repetitions': must be from 1 to 10000, found 9223372036854775807");
  const std::string at_bound = dir.write("exp.toml", experiment_text("name = \"x\"", "", "repetitions = 10000"));
  EXPECT_EQ(error_of(at_bound), "no error");
}

TEST(ExperimentBounds, TheExperimentNameMustBeASafeFileName) {
  test::ScratchDir dir;
  const auto check = [&](const std::string& name_line, const std::string& expected) {
    const std::string path = dir.write("exp.toml", experiment_text(name_line, ""));
    EXPECT_EQ(error_of(path), expected.empty() ? "no error" : path + expected) << name_line;
  };
  check("name = \"../../../tmp/escaped\"",
        ":2:8: key 'experiment.name': must start with a letter or digit (it names the results file results/NAME.db)");
  check("name = \"a/../../escaped\"",
        ":2:8: key 'experiment.name': may hold only letters, digits, spaces and - _ . ( ) + , (it names the results "
        "file results/NAME.db); found '/'");
  check("name = \"nul\\u0000byte\"",
        ":2:8: key 'experiment.name': may hold only letters, digits, spaces and - _ . ( ) + , (it names the results "
        "file results/NAME.db); found byte 0");
  check("name = \"" + std::string(101, 'x') + "\"",
        ":2:8: key 'experiment.name': must be at most 100 bytes (it names files), found 101");
  check("name = \"glare pilot (2026), run-2_b.1\"", "");
  check("name = \"Blendung Pilotstudie ü\"", "");
}

}  // namespace
}  // namespace glarelab
