// Experiment files: TOML (toml++) read strictly through TableReader, plus CSV condition tables.
// Every error names file:line:column and the dotted key so the experimenter can jump to it.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string_view>

#include "core/display_calibration.h"
#include "protocols/adaptive_config.h"
#include "core/number_text.h"
#include "protocols/adjustment_procedure.h"
#include "protocols/block_config.h"
#include "protocols/condition_rows.h"
#include "protocols/csv_table.h"
#include "protocols/display_stereo_config.h"
#include "protocols/forced_choice.h"
#include "protocols/generated_scene_config.h"
#include "protocols/observer_optics_config.h"
#include "protocols/pair_design.h"
#include "protocols/rating_procedure.h"
#include "protocols/scene_file_config.h"
#include "core/real_stimulus.h"
#include "core/text_limits.h"
#include "protocols/stimulus_duration.h"
#include "protocols/straylight_config.h"
#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kSupportedProcedures = {"forced_choice", "staircase", "quest", "quest_plus", "psi", "rating",
                                                      "adjustment", "straylight"};

std::string join_quoted(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "'" : ", '") + item + "'";
  return text;
}

// Relative paths in an experiment file are relative to the file's own directory, so an
// experiment folder can be moved or shared as a whole.
std::string resolve_path(const std::string& base_dir, const std::string& path) {
  fs::path resolved(path);
  if (resolved.is_relative()) resolved = fs::path(base_dir) / resolved;
  return resolved.lexically_normal().string();
}

int read_int(TableReader& reader, std::string_view key, int fallback, std::int64_t minimum, std::int64_t maximum) {
  return static_cast<int>(reader.integer_in_range(key, fallback, minimum, maximum));
}

// Bounds of a display description: what real setups span, with a wide margin. Beyond them a value
// is a typo, and some (a 1e300 Hz refresh, a 1e300 gamma) would only fail later, mid-session.
// 16384 px is the texture size every OpenGL 4.5 implementation must support (GL_MAX_TEXTURE_SIZE).
constexpr std::int64_t kMaxDisplayPx = 16384;
constexpr double kMinRefreshHz = 1.0, kMaxRefreshHz = 1000.0;
constexpr double kMinViewingDistanceMm = 10.0, kMaxViewingDistanceMm = 100000.0;  // 1 cm to 100 m
constexpr double kMinPixelPitchMm = 0.001, kMaxPixelPitchMm = 100.0;
// From a dim CRT to well beyond any HDR display or projector made.
constexpr double kMinPeakLuminanceCdM2 = 0.001, kMaxPeakLuminanceCdM2 = 1e5;
constexpr double kMinGamma = 0.5, kMaxGamma = 5.0;
constexpr std::int64_t kMaxMonitorIndex = 63;
// Pixel values times scale_cd_m2 are luminances: a scale outside this range turns any float image
// into zeros or overflows (1e-300 made every scene black).
constexpr double kMinSceneScale = 1e-9, kMaxSceneScale = 1e9;
// The ages the analytic glare models are given for (glare/analytic/analytic_psf.h, check_observer_eye).
constexpr double kMinObserverAgeYears = 1.0, kMaxObserverAgeYears = 100.0;

// The experiment name names the default database (results/NAME.db) and the analysis folders, so it
// must be a safe file name: "../../../tmp/escaped" once wrote outside results/, and a NUL made
// directories. Letters, digits, UTF-8 text, spaces and - _ . ( ) + , only, starting with a letter,
// digit or UTF-8 character; at most 100 bytes. Empty string: the name is fine.
std::string experiment_name_problem(const std::string& name) {
  constexpr std::size_t kMaxNameBytes = 100;
  if (name.empty()) return "must not be empty";
  if (name.size() > kMaxNameBytes)
    return "must be at most " + std::to_string(kMaxNameBytes) + " bytes (it names files), found " +
           std::to_string(name.size());
  const auto is_plain = [](unsigned char c) { return std::isalnum(c) != 0 || c >= 0x80; };
  if (!is_plain(static_cast<unsigned char>(name.front())))
    return "must start with a letter or digit (it names the results file results/NAME.db)";
  for (const char character : name) {
    const auto c = static_cast<unsigned char>(character);
    if (is_plain(c) || std::string_view(" -_.()+,").find(character) != std::string_view::npos) continue;
    std::string shown = c >= 0x20 && c < 0x7f ? "'" + std::string(1, character) + "'" : "byte " + std::to_string(c);
    return "may hold only letters, digits, spaces and - _ . ( ) + , (it names the results file results/NAME.db); "
           "found " + shown;
  }
  return {};
}

// A required sub-table; `top` reports its absence at the enclosing table.
const toml::table& require_table(TableReader& parent, std::string_view key) {
  const toml::table* table = parent.table(key);
  if (table == nullptr) parent.fail(key, "missing required table [" + parent.key_path(key) + "]");
  return *table;
}

void read_experiment_section(TableReader& top, Experiment& experiment) {
  TableReader reader(require_table(top, "experiment"), "experiment", top.file());
  const std::optional<std::string> name = reader.string("name");
  if (!name) reader.fail("name", "missing required key (a string naming the experiment)");
  if (const std::string problem = experiment_name_problem(*name); !problem.empty()) reader.fail("name", problem);
  experiment.name = *name;
  experiment.description = reader.string("description").value_or("");
  const std::optional<std::int64_t> seed = reader.integer("seed");
  if (seed) {
    if (*seed < 0) reader.fail("seed", "must be >= 0, found " + number_text(*seed));
    experiment.seed = static_cast<std::uint64_t>(*seed);
  }
  reader.report_unused();
}

// [display] encoding = "pq" | "table" and their keys (docs/DISPLAY_CALIBRATION.md). Read before
// the peak, because a calibration table fixes the peak.
void read_display_encoding(TableReader& reader, DisplaySpec& display, const std::string& base_dir) {
  if (const std::optional<std::string> encoding = reader.string("encoding")) {
    if (*encoding == "srgb") {
      display.encoding = DisplayEncoding::srgb;
    } else if (*encoding == "gamma") {
      display.encoding = DisplayEncoding::gamma;
    } else if (*encoding == "pq") {
      display.encoding = DisplayEncoding::pq;
    } else if (*encoding == "table") {
      display.encoding = DisplayEncoding::table;
    } else {
      reader.fail("encoding", "unsupported encoding '" + *encoding + "' (supported: 'srgb', 'gamma', 'pq', 'table')");
    }
  }
  if (const std::optional<std::string> primaries = reader.string("primaries")) {
    if (display.encoding != DisplayEncoding::pq)
      reader.fail_at_key("primaries", "applies only to encoding = 'pq' (the other encodings address the display's own primaries)");
    if (*primaries == "rec709") {
      display.primaries = DisplayPrimaries::rec709;
    } else if (*primaries == "bt2020") {
      display.primaries = DisplayPrimaries::bt2020;
    } else {
      reader.fail("primaries", "unsupported primaries '" + *primaries + "' (supported: 'rec709', 'bt2020')");
    }
  }
  const std::optional<std::string> calibration = reader.string("calibration");
  if (display.encoding == DisplayEncoding::table) {
    if (!calibration)
      reader.fail("encoding", "encoding = 'table' needs calibration = \"FILE.csv\" (docs/DISPLAY_CALIBRATION.md)");
    const std::string path = resolve_path(base_dir, *calibration);
    std::error_code error;
    if (!fs::is_regular_file(path, error)) reader.fail("calibration", "no calibration file " + path);
    display.calibration = read_display_calibration(path);
  } else if (calibration) {
    reader.fail_at_key("calibration", "applies only to encoding = 'table'");
  }
}

void read_display_section(TableReader& top, Experiment& experiment, const std::string& base_dir) {
  const toml::table* table = top.table("display");
  if (table == nullptr) return;
  TableReader reader(*table, "display", top.file());
  DisplaySpec& display = experiment.display;
  display.width_px = read_int(reader, "width_px", display.width_px, 1, kMaxDisplayPx);
  display.height_px = read_int(reader, "height_px", display.height_px, 1, kMaxDisplayPx);
  display.refresh_hz = reader.number_in_range("refresh_hz", display.refresh_hz, kMinRefreshHz, kMaxRefreshHz, "Hz");
  display.viewing_distance_mm = reader.number_in_range("viewing_distance_mm", display.viewing_distance_mm,
                                                       kMinViewingDistanceMm, kMaxViewingDistanceMm, "mm");
  display.pixel_pitch_mm =
      reader.number_in_range("pixel_pitch_mm", display.pixel_pitch_mm, kMinPixelPitchMm, kMaxPixelPitchMm, "mm");
  read_display_encoding(reader, display, base_dir);
  if (display.encoding == DisplayEncoding::table) {
    // The table measures the peak: a [display] peak may restate it (within 1 %), not contradict it.
    const double measured = display.calibration.peak_cd_m2();
    if (const std::optional<double> stated = reader.number("peak_luminance_cd_m2");
        stated && std::abs(*stated - measured) > 0.01 * measured)
      reader.fail("peak_luminance_cd_m2", "contradicts the calibration table's peak " + number_text(measured) +
                                              " cd/m2 (black plus the three channels' full-drive gains); leave it out");
    display.peak_luminance_cd_m2 = measured;
  } else {
    // PQ encodes absolute luminance up to 10000 cd/m2 (SMPTE ST 2084).
    const double max_peak = display.encoding == DisplayEncoding::pq ? 10000.0 : kMaxPeakLuminanceCdM2;
    display.peak_luminance_cd_m2 = reader.number_in_range("peak_luminance_cd_m2", display.peak_luminance_cd_m2,
                                                          kMinPeakLuminanceCdM2, max_peak, "cd/m2");
  }
  // The background is shown on the display, so it cannot exceed the display's peak.
  display.background_cd_m2 = reader.number_in_range("background_cd_m2", display.background_cd_m2, 0.0,
                                                    display.peak_luminance_cd_m2, "cd/m2 (the display's peak)");
  display.gamma = reader.number_in_range("gamma", display.gamma, kMinGamma, kMaxGamma);
  if (const std::optional<std::int64_t> bits = reader.integer("bits_per_channel")) {
    if (*bits != 8 && *bits != 10 && *bits != 16)
      reader.fail("bits_per_channel", "must be 8, 10 or 16 (half float), found " + number_text(*bits));
    display.bits_per_channel = static_cast<int>(*bits);
  }
  // The background between side-by-side stimuli; a gap that leaves no column is refused with the scenes.
  display.stimulus_gap_deg = reader.number_in_range("stimulus_gap_deg", display.stimulus_gap_deg, 0.0, 90.0, "deg");
  experiment.stimulus_gap_where = reader.value_location("stimulus_gap_deg");
  display.monitor = read_int(reader, "monitor", display.monitor, 0, kMaxMonitorIndex);
  display.fullscreen = reader.boolean("fullscreen").value_or(display.fullscreen);
  read_display_stereo(reader, experiment);
  read_display_output(reader, experiment);
  // What makes the frames (stimuli/frame_engine.h; docs/EXPERIMENT_FILES.md): `--engine` wins.
  if (const std::optional<std::string> engine = reader.string("engine")) {
    const std::optional<FrameEngineRequest> parsed = parse_spelling<FrameEngineRequest>(*engine);
    if (!parsed) reader.fail("engine", "unknown value '" + *engine + "' (supported: " + spelling_list<FrameEngineRequest>() + ")");
    experiment.engine = *parsed;
  }
  reader.report_unused();
}

void read_scenes_section(TableReader& top, Experiment& experiment, const std::string& base_dir) {
  TableReader scenes(require_table(top, "scenes"), "scenes", top.file());
  // Scene names are the user's own keys: all of them are consumed here.
  scenes.consume_all();
  const toml::table& table = *top.table("scenes");
  if (table.empty()) scenes.fail("", "at least one scene is required, e.g. a = { file = \"a.exr\" }");
  for (const auto& [key, node] : table) {
    const std::string name(key.str());
    if (!node.is_table()) {
      scenes.fail(name, "expected a table such as { file = \"scene.exr\", scale_cd_m2 = 1.0 } or { generator = ... }, found " +
                            describe_toml_type(node));
    }
    if (name.empty()) scenes.fail_at_key(name, "scene names must not be empty");
    if (is_real_stimulus(name))
      scenes.fail_at_key(name, "scene names starting with 'real:' are reserved: a condition's \"" + name +
                                   "\" names a physical object (core/real_stimulus.h), not a scene of [scenes]");
    TableReader reader(*node.as_table(), "scenes." + name, top.file());
    SceneSpec scene;
    scene.name = name;
    scene.where = to_location(key.source(), top.file());
    if (reader.node("generator") != nullptr) {
      scene.generated = read_generated_scene(reader, experiment.display);
      reader.report_unused();
      experiment.scenes.emplace(name, std::move(scene));
      continue;
    }
    const std::optional<std::string> file = reader.string("file");
    if (!file) reader.fail("file", "missing required key (the OpenEXR image of scene '" + name + "')");
    if (file->empty()) reader.fail("file", "must not be empty");
    scene.file = resolve_path(base_dir, *file);
    scene.scale_cd_m2 = reader.number_in_range("scale_cd_m2", scene.scale_cd_m2, kMinSceneScale, kMaxSceneScale);
    read_scene_file_options(reader, scene);
    reader.report_unused();
    experiment.scenes.emplace(name, std::move(scene));
  }
}

// Returns the generated conditions and blocks of design = "all_pairs" (protocols/pair_design.h).
std::optional<GeneratedDesign> read_procedure_section(TableReader& top, Experiment& experiment) {
  TableReader reader(require_table(top, "procedure"), "procedure", top.file());
  const std::optional<std::string> type = reader.string("type");
  if (!type) reader.fail("type", "missing required key (supported: " + join_quoted(kSupportedProcedures) + ")");
  if (std::find(kSupportedProcedures.begin(), kSupportedProcedures.end(), *type) == kSupportedProcedures.end())
    reader.fail("type", "unsupported procedure '" + *type + "' (supported: " + join_quoted(kSupportedProcedures) + ")");
  experiment.procedure = *type;
  if (experiment.procedure == "rating" || experiment.procedure == "adjustment") {
    read_stimulus_duration(reader, experiment.display.refresh_hz, experiment.forced_choice);
    if (experiment.procedure == "rating") read_rating_procedure(reader, experiment);
    else read_adjustment_procedure(reader, experiment);
    read_block_keys(reader, experiment);
    reader.report_unused();
    return std::nullopt;
  }

  ForcedChoiceSpec& spec = experiment.forced_choice;
  // Two sources side by side; a third alternative is the answer "neither" (Spencer 1995).
  if (const std::optional<std::int64_t> alternatives = reader.integer("alternatives")) {
    if (*alternatives != 2 && *alternatives != 3)
      reader.fail("alternatives", "must be 2 or 3 (two sources, optionally 'neither'), found " +
                                      number_text(*alternatives));
    spec.alternatives = static_cast<int>(*alternatives);
  }
  if (const std::optional<std::string> layout = reader.string("layout")) {
    if (*layout != "side_by_side" && *layout != "sequential")
      reader.fail("layout", "unsupported layout '" + *layout + "' (supported: 'side_by_side', 'sequential')");
    spec.layout = *layout;
  }
  // Default answers name the positions ("left", "right"; sequential: "first", "second"), plus
  // "neither" with a third alternative.
  spec.responses = default_responses_for(spec);
  spec.question = reader.string("question").value_or(spec.question);
  read_stimulus_duration(reader, experiment.display.refresh_hz, spec);
  std::optional<GeneratedDesign> generated;
  if (experiment.procedure == "forced_choice") {
    spec.repetitions = reader.repetitions("repetitions", spec.repetitions);
    spec.counterbalance_sides = reader.boolean("counterbalance_sides").value_or(spec.counterbalance_sides);
    generated = read_pair_design(reader, experiment);
    // The generated design promises every mode equally often on each side.
    if (generated && !spec.counterbalance_sides)
      reader.fail("counterbalance_sides", "design = \"all_pairs\" shows every pair both ways round; remove "
                                          "counterbalance_sides = false");
  } else {
    read_adaptive_procedure(reader, experiment);
  }
  read_block_keys(reader, experiment);
  const auto reserved = [](const ArrayString& name) {
    // "abort" is what a Response carries when the observer quits; it cannot also be an answer.
    if (name.value == "abort") throw ConfigError(name.where, name.key, "'abort' is reserved for ending a session");
    if (name.value == kTimeoutResponse)
      throw ConfigError(name.where, name.key, "'timeout' is reserved for a trial not answered within the response window");
  };
  if (const auto responses = reader.distinct_names("responses", "response", reserved)) {
    if (static_cast<int>(responses->size()) != spec.alternatives) {
      reader.fail("responses", "expected " + std::to_string(spec.alternatives) +
                                   " distinct responses (one per alternative), found " + std::to_string(responses->size()));
    }
    spec.responses.clear();
    for (const ArrayString& name : *responses) spec.responses.push_back(name.value);
  }
  reader.report_unused();
  return generated;
}

// [observer]: the observer's eye as the analytic glare models see it (age: Spencer 1995 Eq. 10 and
// CIE 146:2002; pigmentation: CIE 146:2002), and the simulated observer's subtable.
// [observer.refraction] and [observer] spectacles: the eye's refraction and the spectacles worn by
// default (protocols/observer_optics_config.h; [spectacles] is read before this).
ObserverEye read_observer_section(TableReader& top, Experiment& experiment) {
  ObserverEye eye;
  const toml::table* observers = top.table("observer");
  if (observers == nullptr) return eye;
  TableReader group(*observers, "observer", top.file());
  eye.age_years = group.number_in_range("age_years", eye.age_years, kMinObserverAgeYears, kMaxObserverAgeYears, "years");
  eye.pigmentation = group.number_in_range("pigmentation", eye.pigmentation, 0.0, 1.0);
  read_observer_refraction(group, experiment.observer_optics);
  read_spectacles_worn(group, experiment.observer_optics);
  read_depth_of_field(group, experiment.observer_optics);
  const toml::table* simulated = group.table("simulated");
  group.report_unused();
  if (simulated == nullptr) return eye;
  TableReader reader(*simulated, "observer.simulated", top.file());
  SimulatedObserverSpec& spec = experiment.simulated_observer;
  spec.threshold_log10 = reader.positive_number("threshold_log10", spec.threshold_log10);
  spec.slope = reader.positive_number("slope", spec.slope);
  spec.lapse = reader.non_negative_number("lapse", spec.lapse);
  // A lapse of 0.5 or more would put the asymptote at or below chance in a 2-AFC task.
  if (spec.lapse >= 0.5) reader.fail("lapse", "must be in [0, 0.5), found " + number_text(spec.lapse));
  spec.response_time_median_s =
      reader.positive_number("response_time_median_s", spec.response_time_median_s);
  spec.rating_sd = reader.non_negative_number("rating_sd", spec.rating_sd);
  spec.match_sd_log10 = reader.non_negative_number("match_sd_log10", spec.match_sd_log10);
  spec.preferences = read_preferences(reader);
  spec.glare_brightening_per_gain =
      reader.number_in_range("glare_brightening_per_gain", spec.glare_brightening_per_gain, 0.0, 100.0);
  spec.appearance_sd_log10 = reader.number_in_range("appearance_sd_log10", spec.appearance_sd_log10, 1e-6, 10.0);
  spec.neither_band_log10 = reader.number_in_range("neither_band_log10", spec.neither_band_log10, 0.0, 10.0);
  if (const toml::table* modes = reader.table("glare_mode_brightening")) {
    TableReader brightening(*modes, reader.key_path("glare_mode_brightening"), reader.file());
    for (const auto& [key, node] : *modes) {
      const std::string mode(key.str());
      if (mode != "control" && mode != "static" && mode != "dynamic")
        brightening.fail_at_key(mode, "expected a glare mode: control, static or dynamic");
      spec.glare_mode_brightening[mode] = brightening.number_in_range(mode, 0.0, 0.0, 100.0);
    }
    brightening.report_unused();
  }
  reader.report_unused();
  return eye;
}

ConditionSource read_conditions_section(TableReader& top, const std::string& base_dir) {
  TableReader reader(require_table(top, "conditions"), "conditions", top.file());
  const toml::node* file_node = reader.node("file");
  const toml::node* rows_node = reader.node("rows");
  reader.report_unused();
  if (file_node != nullptr && rows_node != nullptr) {
    // Point at whichever of the two was written second: that is the one that conflicts.
    const bool file_later = reader.key_location("file").line > reader.key_location("rows").line ||
                            (reader.key_location("file").line == reader.key_location("rows").line &&
                             reader.key_location("file").column > reader.key_location("rows").column);
    reader.fail_at_key(file_later ? "file" : "rows",
                       "give either 'file' (a CSV table) or 'rows' (inline rows), not both");
  }
  if (file_node == nullptr && rows_node == nullptr) {
    reader.fail("", "missing condition table: give file = \"conditions.csv\" or [[conditions.rows]]");
  }
  ConditionSource source;
  std::vector<LocatedRow>& rows = source.rows;
  if (file_node != nullptr) {
    const std::string path = resolve_path(base_dir, *reader.string("file"));
    std::error_code error;
    if (!fs::is_regular_file(path, error)) reader.fail_at_key("file", "condition table '" + path + "': file not found");
    rows_from_csv_file(path, reader.key_location("file"), source);
    if (rows.empty()) reader.fail("file", "condition table '" + path + "' has a header but no rows");
  } else {
    rows = rows_from_toml(*reader.array("rows"), reader.key_path("rows"), top.file());
    if (rows.empty()) reader.fail("rows", "at least one condition row is required");
  }
  for (std::size_t i = 0; i < rows.size(); ++i) rows[i].row.number = static_cast<int>(i + 1);
  return source;
}

}  // namespace

Experiment parse_experiment_text(const std::string& toml_text, const std::string& origin_name,
                                 const std::string& base_dir) {
  // Size and nesting first: toml++ recurses per level and a deep dotted key overflows its stack.
  if (const std::optional<TextLimitFault> fault = toml_limit_fault(toml_text))
    throw ConfigError(SourceLocation{origin_name, static_cast<int>(fault->line), static_cast<int>(fault->column)}, "",
                      fault->message);
  toml::table root;
  try {
    root = toml::parse(std::string_view(toml_text), std::string_view(origin_name));
  } catch (const toml::parse_error& error) {
    throw ConfigError(to_location(error.source(), origin_name), "",
                      "TOML syntax error: " + std::string(error.description()));
  }
  const std::string base = fs::absolute(fs::path(base_dir)).lexically_normal().string();

  Experiment experiment;
  experiment.source_file = origin_name;
  TableReader top(root, "", origin_name);
  // Declare the top-level tables before reading any, so a misspelt [procedur] is reported as
  // such rather than as a missing [procedure].
  for (const char* section :
       {"experiment", "display", "scenes", "procedure", "conditions", "observer", "spectacles", "glare", "perception",
        "presentation", "analysis"}) {
    top.node(section);
  }
  top.node("blocks");  // [[blocks]] (protocols/block_config.h)
  top.report_unused();

  read_experiment_section(top, experiment);
  read_display_section(top, experiment, base);
  const bool straylight = read_straylight_design(top, experiment);  // its own stimulus: no scenes, conditions or blocks
  if (!straylight) read_scenes_section(top, experiment, base);
  const std::optional<GeneratedDesign> generated = straylight ? std::nullopt : read_procedure_section(top, experiment);
  ConditionSource conditions = generated ? generated_conditions(top, *generated, experiment)
                               : straylight ? ConditionSource{} : read_conditions_section(top, base);
  if (!generated && !straylight) read_blocks_section(top, experiment);
  read_spectacles_section(top, experiment.observer_optics);
  const ObserverEye observer_eye = read_observer_section(top, experiment);
  set_glare_observer_eye(top, experiment, read_glare_section(top), observer_eye);
  experiment.perception = read_perception_section(top);
  experiment.analysis = read_analysis_section(top);
  experiment.presentation = read_presentation_section(top, experiment);

  check_condition_scenes(conditions, experiment);
  experiment.conditions.reserve(conditions.rows.size());
  for (LocatedRow& located : conditions.rows) {
    try {  // each refusal at the bad value's own cell (at_value_cell)
      glare_mode_for(experiment.glare, located.row);  // an unknown 'glare' value stops here
      glare_model_for(experiment.glare, located.row);  // so do an unknown 'glare_model' and a bad 'glare_gain'
      glare_gain_for(located.row);
      perception_for(experiment.perception, located.row);  // and an unknown stage in 'perception'
      spectacles_for(experiment.observer_optics, located.row);  // and spectacles no table describes
      if (position_glare_modes(located.row) && experiment.procedure != "forced_choice")
        throw ConfigError(located.row.where, "condition '" + located.row.name() + "' glare_a",
                          "a glare mode per side (glare_a, glare_b) is for forced choice only");
    } catch (const ConfigError& error) {
      throw at_value_cell(error, located);
    }
    experiment.conditions.push_back(std::move(located.row));
  }
  if (experiment.procedure == "staircase" || experiment.procedure == "quest" || experiment.procedure == "quest_plus" ||
      experiment.procedure == "psi") {
    expand_tracks_per_condition(experiment);
    check_adaptive_conditions(experiment);
  }
  check_blocks(experiment);
  check_preferences(experiment);
  return experiment;
}

Experiment load_experiment(const std::string& path) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) throw ConfigError(SourceLocation{path, 0, 0}, "", "file not found");
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) throw ConfigError(SourceLocation{path, 0, 0}, "", "cannot be opened");
  if (const auto bytes = fs::file_size(path, error); !error && bytes > kMaxTomlBytes)  // refused before it is read
    throw ConfigError(SourceLocation{path, 0, 0}, "", "the file is " + std::to_string(bytes) +
                                                          " bytes; glarelab reads experiment files of at most 64 MiB");
  std::ostringstream text;
  text << in.rdbuf();
  const fs::path absolute = fs::absolute(fs::path(path)).lexically_normal();
  return parse_experiment_text(text.str(), absolute.string(), absolute.parent_path().string());
}

}  // namespace glarelab
