// [observer.refraction], [spectacles.NAME] and the "spectacles" column, read strictly through
// TableReader: an unknown key, a value out of range or a cylinder of the wrong sign stops the run at
// its place in the file. The ranges are what a real eye or lens can be; beyond them a value is a typo.
#include "protocols/observer_optics_config.h"

#include <cmath>
#include <optional>
#include <string_view>

#include "core/number_text.h"
#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {
namespace {

// Refractive errors of living eyes run to about -30 D (pathological myopia) and +20 D (aphakia);
// cylinders beyond 10 D are keratoconus territory that sphero-cylinders do not describe.
constexpr double kMaxSphereDioptres = 30.0;
constexpr double kMaxCylinderDioptres = 10.0;
constexpr double kMaxVertexDistanceMm = 30.0;
// Duane's (1922) largest amplitudes, in children, are about 14 D; 20 leaves room and no more.
constexpr double kMaxAmplitudeDioptres = 20.0;

// sphere, cylinder, axis and cylinder_form of a table, in minus-cylinder form.
SpheroCylinder read_sphero_cylinder(TableReader& reader) {
  SpheroCylinder lens;
  lens.sphere_dioptres = reader.number_in_range("sphere_dioptres", 0.0, -kMaxSphereDioptres, kMaxSphereDioptres, "D");
  lens.cylinder_dioptres =
      reader.number_in_range("cylinder_dioptres", 0.0, -kMaxCylinderDioptres, kMaxCylinderDioptres, "D");
  // TABO axes are written from 1 to 180 on prescriptions (180 rather than 0); both mean horizontal.
  lens.axis_deg = reader.number_in_range("axis_deg", 0.0, 0.0, 180.0, "degrees (TABO)");
  if (lens.axis_deg == 180.0) lens.axis_deg = 0.0;
  const std::string form = reader.string("cylinder_form").value_or("minus");
  if (form != "minus" && form != "plus")
    reader.fail("cylinder_form", "must be \"minus\" or \"plus\", found \"" + form + "\"");
  if (form == "minus" && lens.cylinder_dioptres > 0.0)
    reader.fail("cylinder_dioptres",
                "is positive, but cylinders are read in minus-cylinder form; write the transposed prescription (" +
                    number_text(lens.sphere_dioptres + lens.cylinder_dioptres) + " / " + number_text(-lens.cylinder_dioptres) +
                    " x " + number_text(std::fmod(lens.axis_deg + 90.0, 180.0)) +
                    ") or say cylinder_form = \"plus\"");
  if (form == "plus" && lens.cylinder_dioptres < 0.0)
    reader.fail("cylinder_dioptres", "is negative, but cylinder_form = \"plus\" says the cylinder is written plus");
  if (form == "plus" && lens.cylinder_dioptres != 0.0) {
    lens.sphere_dioptres += lens.cylinder_dioptres;
    lens.cylinder_dioptres = -lens.cylinder_dioptres;
    lens.axis_deg = std::fmod(lens.axis_deg + 90.0, 180.0);
  }
  if (lens.cylinder_dioptres == 0.0) lens.axis_deg = 0.0;  // no cylinder, no axis
  return lens;
}

double read_vertex_distance(TableReader& reader) {
  const double value = reader.number_in_range("vertex_distance_mm", 12.0, 0.0, kMaxVertexDistanceMm, "mm");
  if (value <= 0.0) reader.fail("vertex_distance_mm", "must be > 0: the lens sits in front of the cornea");
  return value;
}

toml::table sphero_cylinder_toml(const SpheroCylinder& lens) {
  return toml::table{{"sphere_dioptres", lens.sphere_dioptres},
                     {"cylinder_dioptres", lens.cylinder_dioptres},
                     {"axis_deg", lens.axis_deg},
                     {"cylinder_form", "minus"}};
}

}  // namespace

void read_observer_refraction(TableReader& observer, ObserverOptics& optics) {
  const toml::table* table = observer.table("refraction");
  if (table == nullptr) return;
  TableReader reader(*table, "observer.refraction", observer.file());
  ObserverRefractionSettings& refraction = optics.refraction;
  refraction.prescription = read_sphero_cylinder(reader);
  refraction.vertex_distance_mm = read_vertex_distance(reader);
  if (reader.number("accommodation_amplitude_dioptres"))
    refraction.accommodation_amplitude_dioptres =
        reader.number_in_range("accommodation_amplitude_dioptres", 0.0, 0.0, kMaxAmplitudeDioptres, "D");
  reader.report_unused();
  optics.refraction_stated = true;
}

void read_spectacles_section(TableReader& top, ObserverOptics& optics) {
  const toml::table* section = top.table("spectacles");
  if (section == nullptr) return;
  TableReader names(*section, "spectacles", top.file());
  for (const auto& [key, node] : *section) {
    const std::string name(key.str());
    if (name == "none") names.fail_at_key(name, "'none' means no spectacles; name the pair something else");
    const toml::table* table = names.table(name);
    if (table == nullptr) names.fail(name, "expected a table [spectacles." + name + "] describing a pair of spectacles");
    TableReader reader(*table, "spectacles." + name, top.file());
    SpectaclesSettings pair;
    pair.name = name;
    pair.prescription = read_sphero_cylinder(reader);
    pair.vertex_distance_mm = read_vertex_distance(reader);
    // Glasses run from n = 1.498 (CR-39) to 1.9 (high-index glass); below 1 a lens would not bend
    // light the way a lens does at all.
    pair.refractive_index = reader.number_in_range("refractive_index", pair.refractive_index, 1.0, 2.5);
    if (pair.refractive_index <= 1.0) reader.fail("refractive_index", "must be > 1 (air is 1): found " + number_text(pair.refractive_index));
    pair.abbe_number = reader.number_in_range("abbe_number", pair.abbe_number, 0.0, 120.0);
    if (pair.abbe_number <= 0.0) reader.fail("abbe_number", "must be > 0: found " + number_text(pair.abbe_number));
    pair.near_add_dioptres = reader.number_in_range("near_add_dioptres", 0.0, 0.0, 4.0, "D");
    pair.decentration_x_mm = reader.number_in_range("decentration_x_mm", 0.0, -20.0, 20.0, "mm");
    pair.decentration_y_mm = reader.number_in_range("decentration_y_mm", 0.0, -20.0, 20.0, "mm");
    reader.report_unused();
    optics.spectacles.push_back(pair);
  }
}

void read_spectacles_worn(TableReader& observer, ObserverOptics& optics) {
  const std::optional<std::string> worn = observer.string("spectacles");
  if (!worn) return;
  if (*worn != "none" && optics.find_spectacles(*worn) == nullptr)
    observer.fail("spectacles", "no [spectacles." + *worn + "] table describes '" + *worn + "' (or write \"none\")");
  optics.spectacles_worn = *worn;
}

void read_depth_of_field(TableReader& observer, ObserverOptics& optics) {
  const std::optional<bool> on = observer.boolean("depth_of_field");
  if (on) {
    optics.depth_of_field = *on;
    optics.depth_of_field_where = observer.value_location("depth_of_field").to_string();
  }
  const std::optional<std::string> rule = observer.string("accommodation");
  if (!rule) return;
  const std::optional<AccommodationRule> parsed = parse_spelling<AccommodationRule>(*rule);
  if (!parsed)
    observer.fail("accommodation", "unknown value '" + *rule + "' (supported: " + spelling_list<AccommodationRule>() + ")");
  // The rule says how the depth of field blurs each depth; a flat display has one depth, which both
  // rules bring into focus alike, so "range" without the depth of field would change nothing.
  if (*parsed == AccommodationRule::range && on == false)
    observer.fail("accommodation", "\"range\" accommodates each depth of the scene, but depth_of_field = false turns "
                                   "the depth of field off: remove one of the two");
  optics.accommodation = *parsed;
}

const SpectaclesSettings* spectacles_for(const ObserverOptics& optics, const ConditionRow& row) {
  const std::string* column = row.find("spectacles");
  const std::string name = column != nullptr && !column->empty() ? *column : optics.spectacles_worn;
  if (name == "none") return nullptr;
  const SpectaclesSettings* pair = optics.find_spectacles(name);
  if (pair == nullptr)
    throw ConfigError(row.where, "condition '" + row.name() + "' spectacles",
                      "no [spectacles." + name + "] table describes '" + name + "' (or write \"none\")");
  return pair;
}

toml::table refraction_toml(const ObserverRefractionSettings& refraction) {
  toml::table table = sphero_cylinder_toml(refraction.prescription);
  table.insert("vertex_distance_mm", refraction.vertex_distance_mm);
  if (refraction.accommodation_amplitude_dioptres >= 0.0)
    table.insert("accommodation_amplitude_dioptres", refraction.accommodation_amplitude_dioptres);
  return table;
}

toml::table spectacles_section_toml(const ObserverOptics& optics) {
  toml::table section;
  for (const SpectaclesSettings& pair : optics.spectacles) {
    toml::table table = sphero_cylinder_toml(pair.prescription);
    table.insert("vertex_distance_mm", pair.vertex_distance_mm);
    table.insert("refractive_index", pair.refractive_index);
    table.insert("abbe_number", pair.abbe_number);
    table.insert("near_add_dioptres", pair.near_add_dioptres);
    table.insert("decentration_x_mm", pair.decentration_x_mm);
    table.insert("decentration_y_mm", pair.decentration_y_mm);
    section.insert(pair.name, std::move(table));
  }
  return section;
}

}  // namespace glarelab
