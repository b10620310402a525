#pragma once
// An experiment as described by its TOML file (and CSV condition tables), fully resolved:
// defaults filled, paths absolute, tables inlined. See docs/EXPERIMENT_FILES.md for the format.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "protocols/config_error.h"
#include "protocols/glare_config.h"

namespace glarelab {

enum class DisplayEncoding { srgb, gamma };

struct DisplaySpec {
  int width_px = 1280;
  int height_px = 720;
  double refresh_hz = 60.0;
  double viewing_distance_mm = 600.0;
  double pixel_pitch_mm = 0.25;
  double peak_luminance_cd_m2 = 250.0;  // white of the display; brighter stimulus values clip
  double background_cd_m2 = 0.0;        // luminance around and between stimuli
  DisplayEncoding encoding = DisplayEncoding::srgb;
  double gamma = 2.2;  // used when encoding == gamma
  int monitor = 0;
  bool fullscreen = false;
};

struct SceneSpec {
  std::string name;
  std::string file;            // absolute path of the OpenEXR image
  double scale_cd_m2 = 1.0;    // multiplies pixel values to give luminance in cd/m2
  SourceLocation where;
};

// One row of the condition table, column order kept.
struct ConditionRow {
  std::vector<std::pair<std::string, std::string>> fields;
  SourceLocation where;
  int number = 0;  // 1-based position in the condition table, for name()
  const std::string* find(const std::string& column) const;
  std::string name() const;  // the "name" column, or "row N"
};

struct ForcedChoiceSpec {
  int alternatives = 2;
  std::string layout = "side_by_side";
  std::string question = "Which light is brighter?";
  int stimulus_frames = 30;
  int repetitions = 1;
  bool counterbalance_sides = true;
  std::vector<std::string> responses = {"left", "right"};
};

struct SimulatedObserverSpec {
  // 2-AFC Weibull psychometric function of the |log10| luminance ratio of the two sources.
  double threshold_log10 = 0.05;
  double slope = 3.5;
  double lapse = 0.02;
  double response_time_median_s = 0.6;
};

struct Experiment {
  std::string source_file;  // absolute path of the TOML file (or "<stored config>")
  std::string name;
  std::string description;
  std::uint64_t seed = 1;
  DisplaySpec display;
  std::map<std::string, SceneSpec> scenes;
  std::string procedure = "forced_choice";
  ForcedChoiceSpec forced_choice;
  std::vector<ConditionRow> conditions;
  SimulatedObserverSpec simulated_observer;
  GlareSpec glare;  // [glare] and the default glare mode of conditions
};

// Parses and validates a file. Throws ConfigError (file:line:column, key) for syntax errors,
// unknown keys, wrong types, out-of-range values, missing CSV files or columns, and conditions
// that name unknown scenes. Scene files are not opened here (see stimuli/scene_library.h).
Experiment load_experiment(const std::string& path);
// The same from text; relative paths resolve against base_dir.
Experiment parse_experiment_text(const std::string& toml_text, const std::string& origin_name,
                                 const std::string& base_dir);

// The fully resolved experiment as TOML (defaults explicit, absolute paths, conditions inline as
// [[conditions.rows]]). parse_experiment_text(resolved_config_toml(e), ...) gives back e.
std::string resolved_config_toml(const Experiment& experiment);

}  // namespace glarelab
