// [glare] table and the "glare" condition column. Read through TableReader so a misspelt key stops
// the run (protocols/toml_table_reader.h).
#include "protocols/glare_config.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <string_view>

#include "core/number_text.h"
#include "glare/eye/eye_parameters.h"
#include "glare/analytic/hybrid_handover.h"
#include "protocols/eye_parameters_config.h"
#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {
namespace {

int read_bounded_int(TableReader& reader, std::string_view key, int fallback, int minimum, int maximum) {
  const std::optional<std::int64_t> value = reader.integer(key);
  if (!value) return fallback;
  if (*value < minimum || *value > maximum)
    reader.fail(key, "must be in [" + number_text(minimum) + ", " + number_text(maximum) + "], found " +
                         number_text(*value));
  return static_cast<int>(*value);
}

std::string read_choice(TableReader& reader, std::string_view key, const std::string& fallback,
                        std::initializer_list<const char*> choices) {
  const std::optional<std::string> value = reader.string(key);
  if (!value) return fallback;
  std::string listed;
  for (const char* choice : choices) {
    if (*value == choice) return *value;
    listed += std::string(listed.empty() ? "" : ", ") + "'" + choice + "'";
  }
  reader.fail(key, "unknown value '" + *value + "' (supported: " + listed + ")");
}

// A choice spelt by its enumeration's table (core/spelling.h); another text stops the run at the
// value, listing the accepted ones.
template <typename Enum>
Enum read_choice(TableReader& reader, std::string_view key, Enum fallback) {
  const std::optional<std::string> value = reader.string(key);
  if (!value) return fallback;
  if (const std::optional<Enum> parsed = parse_spelling<Enum>(*value)) return *parsed;
  reader.fail(key, "unknown value '" + *value + "' (supported: " + spelling_list<Enum>() + ")");
}

GlareMode parse_mode_at(const std::string& name, const SourceLocation& where, const std::string& key) {
  if (name == "dynamic") return GlareMode::dynamic;
  if (name == "static") return GlareMode::static_eye;
  if (name == "control") return GlareMode::control;
  throw ConfigError(where, key, "unknown glare mode '" + name + "' (supported: 'dynamic', 'static', 'control')");
}

}  // namespace

namespace {
// Straylight from below the clearest young eyes (about 0.6) to dense cataract (about 2.2); within
// these bounds a CIE eye may still scatter more than all the light, checked with the pigmentation.
constexpr double kMinStraylightLog10 = 0.4, kMaxStraylightLog10 = 2.5;
}  // namespace

GlareSpec read_glare_section(TableReader& top) {
  GlareSpec spec;
  const toml::table* table = top.table("glare");
  if (table == nullptr) return spec;
  TableReader reader(*table, "glare", top.file());
  if (const std::optional<std::string> mode = reader.string("mode"))
    spec.mode = parse_mode_at(*mode, reader.value_location("mode"), reader.key_path("mode"));
  spec.static_time_s = reader.non_negative_number("static_time_s", spec.static_time_s);
  // The eye model answers up to 24 h (glare/eye/eye_parameters.h): a larger instant is a mistake.
  if (spec.static_time_s > kMaxEyeModelTime_s) {
    std::ostringstream found;
    found << spec.static_time_s;
    reader.fail("static_time_s", std::string("must be at most ") + kMaxEyeModelTimeText + ", found " + found.str());
  }
  spec.grid_px = read_bounded_int(reader, "grid_px", spec.grid_px, 16, 8192);
  // The grid's centre pixel N/2 is the optical axis and the PSF's DC term.
  if (spec.grid_px % 2 != 0) reader.fail("grid_px", "must be even, found " + std::to_string(spec.grid_px));
  spec.aperture_width_mm = reader.positive_number("aperture_width_mm", spec.aperture_width_mm);
  spec.supersampling = read_bounded_int(reader, "supersampling", spec.supersampling, 2, 16);
  spec.wavelength_samples = read_bounded_int(reader, "wavelength_samples", spec.wavelength_samples, 1, 1024);
  spec.visibility_weber_fraction =
      reader.positive_number("visibility_weber_fraction", spec.visibility_weber_fraction);
  spec.visibility_floor_cd_m2 = reader.positive_number("visibility_floor_cd_m2", spec.visibility_floor_cd_m2);
  spec.skip_invisible = reader.boolean("skip_invisible").value_or(spec.skip_invisible);
  spec.backend = read_choice(reader, "backend", spec.backend);
  // The GL FFT takes powers of two from 16 to 4096 (glare/gl/fft.h): refused here, not mid-session.
  if (spec.backend == GlareBackendRequest::gl && (spec.grid_px > 4096 || !std::has_single_bit(static_cast<unsigned>(spec.grid_px))))
    reader.fail("backend", "'gl' needs grid_px a power of two from 16 to 4096, found grid_px = " +
                               std::to_string(spec.grid_px) + " (use \"cpu\" or change grid_px)");
  if (const std::optional<std::int64_t> window = reader.integer("gaze_window_px")) {
    if (*window != 0 && (*window < 16 || *window > 8192 || !std::has_single_bit(static_cast<std::uint64_t>(*window))))
      reader.fail("gaze_window_px", "must be 0 (whole frame) or a power of two from 16 to 8192, found " +
                                        number_text(*window));
    spec.gaze_window_px = static_cast<int>(*window);
  }
  spec.gaze_latency_compensation = reader.boolean("gaze_latency_compensation").value_or(spec.gaze_latency_compensation);
  spec.pupil_source = read_choice(reader, "pupil_source", spec.pupil_source);
  spec.blink_source = read_choice(reader, "blink_source", spec.blink_source);
  spec.presentation = read_choice(reader, "presentation", spec.presentation);
  spec.model = parse_glare_model(
      read_choice(reader, "model", to_string(spec.model), {"human", "ritschel", "spencer", "cie", "hybrid", "luidolt"}));
  spec.spencer_regime = parse_spencer_regime(
      read_choice(reader, "regime", to_string(spec.spencer_regime), {"adaptive", "photopic", "mesopic", "scotopic"}));
  spec.hybrid_far_field =
      parse_glare_model(read_choice(reader, "hybrid_far_field", to_string(spec.hybrid_far_field), {"spencer", "cie"}));
  spec.spencer_flare_lines = reader.boolean("spencer_flare_lines").value_or(spec.spencer_flare_lines);
  spec.source = read_choice(reader, "source", spec.source);
  // The participant's measured straylight, log10(s) at 7 degrees (docs/STRAYLIGHT.md): the CIE
  // far field (of the human eye, the hybrid's and the cie model) scaled to it. Whether a CIE eye of
  // the observer's pigmentation can have it is checked once [observer] is read (experiment_file.cpp);
  // "measured" is read there too (protocols/straylight_config.h).
  if (const toml::node* straylight = reader.node("straylight"); straylight != nullptr && !straylight->is_string())
    spec.observer_eye.straylight_log_s =
        reader.number_in_range("straylight", 0.0, kMinStraylightLog10, kMaxStraylightLog10, "log10(deg^2/sr)");
  // The hand-over annulus: both or neither (0: the default for the grid's reach).
  const bool inner_given = reader.node("hybrid_handover_inner_deg") != nullptr,
             outer_given = reader.node("hybrid_handover_outer_deg") != nullptr;
  spec.hybrid_handover_inner_deg = reader.positive_number("hybrid_handover_inner_deg", 0.0);
  spec.hybrid_handover_outer_deg = reader.positive_number("hybrid_handover_outer_deg", 0.0);
  if (inner_given != outer_given)
    reader.fail(inner_given ? "hybrid_handover_inner_deg" : "hybrid_handover_outer_deg",
                "the hand-over annulus needs both hybrid_handover_inner_deg and hybrid_handover_outer_deg");
  if (outer_given) {
    const double reach = wave_psf_reach_for_aperture_deg(spec.grid_px, spec.aperture_width_mm);
    try {
      check_handover(HybridHandover{spec.hybrid_handover_inner_deg, spec.hybrid_handover_outer_deg}, reach);
    } catch (const HandoverError& error) {
      reader.fail("hybrid_handover_outer_deg", error.what());
    }
  }
  read_glare_eye(reader, spec.eye);
  reader.report_unused();
  return spec;
}

toml::table glare_section_toml(const GlareSpec& spec) {
  const char* mode = spec.mode == GlareMode::dynamic ? "dynamic" : spec.mode == GlareMode::static_eye ? "static" : "control";
  toml::table table{{"mode", mode},
                     {"static_time_s", spec.static_time_s},
                     {"grid_px", spec.grid_px},
                     {"aperture_width_mm", spec.aperture_width_mm},
                     {"supersampling", spec.supersampling},
                     {"wavelength_samples", spec.wavelength_samples},
                     {"visibility_weber_fraction", spec.visibility_weber_fraction},
                     {"visibility_floor_cd_m2", spec.visibility_floor_cd_m2},
                     {"skip_invisible", spec.skip_invisible},
                     {"backend", std::string(spelling(spec.backend))},
                     {"gaze_window_px", spec.gaze_window_px},
                     {"gaze_latency_compensation", spec.gaze_latency_compensation},
                     {"pupil_source", std::string(spelling(spec.pupil_source))},
                     {"blink_source", std::string(spelling(spec.blink_source))},
                     {"presentation", std::string(spelling(spec.presentation))},
                     {"model", to_string(spec.model)},
                     {"regime", to_string(spec.spencer_regime)},
                     {"spencer_flare_lines", spec.spencer_flare_lines},
                     {"hybrid_far_field", to_string(spec.hybrid_far_field)},
                     {"source", std::string(spelling(spec.source))}};
  if (spec.hybrid_handover_outer_deg > 0.0) {
    table.insert("hybrid_handover_inner_deg", spec.hybrid_handover_inner_deg);
    table.insert("hybrid_handover_outer_deg", spec.hybrid_handover_outer_deg);
  }
  // The straylight the session's glare used (measured or stated), in the session's stored config.
  if (spec.observer_eye.straylight_log_s) table.insert("straylight", *spec.observer_eye.straylight_log_s);
  table.insert("eye", glare_eye_toml(spec.eye));
  return table;
}

std::optional<std::pair<GlareMode, GlareMode>> position_glare_modes(const ConditionRow& row) {
  const std::string* a = row.find("glare_a");
  const std::string* b = row.find("glare_b");
  if (a == nullptr && b == nullptr) return std::nullopt;
  const std::string at = "condition '" + row.name() + "' ";
  if (a == nullptr || b == nullptr)
    throw ConfigError(row.where, at + (a == nullptr ? "glare_a" : "glare_b"),
                      "missing: glare_a and glare_b go together (the glare mode of scene_a and of scene_b)");
  if (const std::string* whole = row.find("glare"); whole != nullptr && !whole->empty())
    throw ConfigError(row.where, at + "glare",
                      "a row with glare_a and glare_b has a mode per side; a 'glare' column for the whole frame "
                      "contradicts them");
  return std::pair{parse_mode_at(*a, row.where, at + "glare_a"), parse_mode_at(*b, row.where, at + "glare_b")};
}

GlareModel glare_model_for(const GlareSpec& spec, const ConditionRow& row) {
  const std::string* value = row.find("glare_model");
  if (value == nullptr || value->empty()) return spec.model;
  try {
    return parse_glare_model(*value);
  } catch (const std::invalid_argument& error) {
    throw ConfigError(row.where, "condition '" + row.name() + "' glare_model", error.what());
  }
}

double glare_gain_for(const ConditionRow& row) {
  const std::string* value = row.find("glare_gain");
  if (value == nullptr || value->empty()) return 1.0;
  const std::string key = "condition '" + row.name() + "' glare_gain";
  double gain = 0.0;
  std::istringstream in(*value);
  if (!(in >> gain) || !(in >> std::ws).eof() || !std::isfinite(gain) || gain < 0.0 || gain > kMaxGlareGain)
    throw ConfigError(row.where, key,
                      "must be a number from 0 to " + number_text(kMaxGlareGain) + " (a gain on the glare), found '" + *value + "'");
  return gain;
}

GlareMode glare_mode_for(const GlareSpec& spec, const ConditionRow& row) {
  const std::string* value = row.find("glare");
  if (value == nullptr || value->empty()) return spec.mode;
  return parse_mode_at(*value, row.where, "condition '" + row.name() + "' glare");
}

}  // namespace glarelab
