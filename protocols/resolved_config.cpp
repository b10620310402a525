// The experiment as it will actually run, written back as TOML: every default explicit, every
// path absolute, the condition table inline. Stored with each session, it reproduces the session
// without the original files, and it reads back through the same strict parser.
#include <limits>
#include <sstream>
#include <stdexcept>

#include <toml++/toml.h>

#include "protocols/experiment.h"

namespace glarelab {
namespace {

// toml++ prints sub-tables in key order; printing each section from its own one-entry root
// keeps the order of the documentation (experiment, display, scenes, procedure, ...).
void print_section(std::ostringstream& out, const std::string& name, toml::table section) {
  toml::table root;
  root.insert(name, std::move(section));
  out << root << "\n\n";
}

}  // namespace

std::string resolved_config_toml(const Experiment& experiment) {
  if (experiment.seed > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
    // TOML integers are signed 64-bit; a larger seed could not be read back.
    throw std::out_of_range("seed " + std::to_string(experiment.seed) + " does not fit a TOML integer");
  }
  std::ostringstream out;
  out << "# Resolved experiment configuration (defaults explicit, paths absolute).\n\n";

  print_section(out, "experiment",
                toml::table{{"name", experiment.name},
                            {"description", experiment.description},
                            {"seed", static_cast<std::int64_t>(experiment.seed)}});

  const DisplaySpec& display = experiment.display;
  print_section(out, "display",
                toml::table{{"width_px", display.width_px},
                            {"height_px", display.height_px},
                            {"refresh_hz", display.refresh_hz},
                            {"viewing_distance_mm", display.viewing_distance_mm},
                            {"pixel_pitch_mm", display.pixel_pitch_mm},
                            {"peak_luminance_cd_m2", display.peak_luminance_cd_m2},
                            {"background_cd_m2", display.background_cd_m2},
                            {"encoding", display.encoding == DisplayEncoding::srgb ? "srgb" : "gamma"},
                            {"gamma", display.gamma},
                            {"monitor", display.monitor},
                            {"fullscreen", display.fullscreen}});

  toml::table scenes;
  for (const auto& [name, scene] : experiment.scenes) {
    toml::table entry{{"file", scene.file}, {"scale_cd_m2", scene.scale_cd_m2}};
    entry.is_inline(true);
    scenes.insert(name, std::move(entry));
  }
  print_section(out, "scenes", std::move(scenes));

  const ForcedChoiceSpec& spec = experiment.forced_choice;
  toml::array responses;
  for (const std::string& response : spec.responses) responses.push_back(response);
  print_section(out, "procedure",
                toml::table{{"type", experiment.procedure},
                            {"alternatives", spec.alternatives},
                            {"layout", spec.layout},
                            {"question", spec.question},
                            {"stimulus_frames", spec.stimulus_frames},
                            {"repetitions", spec.repetitions},
                            {"counterbalance_sides", spec.counterbalance_sides},
                            {"responses", std::move(responses)}});

  const SimulatedObserverSpec& observer = experiment.simulated_observer;
  toml::table simulated{{"threshold_log10", observer.threshold_log10},
                        {"slope", observer.slope},
                        {"lapse", observer.lapse},
                        {"response_time_median_s", observer.response_time_median_s}};
  print_section(out, "observer", toml::table{{"simulated", std::move(simulated)}});
  print_section(out, "glare", glare_section_toml(experiment.glare));

  // Rows are written key by key in column order (toml++ would sort the keys of a whole table);
  // each line is still formatted by toml++, so keys and values are quoted correctly. The parser
  // restores column order from the keys' positions.
  for (const ConditionRow& row : experiment.conditions) {
    out << "[[conditions.rows]]\n";
    for (const auto& [column, value] : row.fields) out << toml::table{{column, value}} << "\n";
    out << "\n";
  }
  return out.str();
}

}  // namespace glarelab
