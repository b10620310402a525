#pragma once
// Reading the observer's refraction and the spectacles of an experiment file into
// core/observer_optics.h (docs/EXPERIMENT_FILES.md, "The observer's eye and spectacles"):
//   [observer.refraction]   sphere_dioptres, cylinder_dioptres, axis_deg, cylinder_form,
//                           vertex_distance_mm, accommodation_amplitude_dioptres
//   [spectacles.NAME]       sphere_dioptres, cylinder_dioptres, axis_deg, cylinder_form,
//                           vertex_distance_mm, refractive_index, abbe_number, near_add_dioptres,
//                           decentration_x_mm, decentration_y_mm
//   [observer] spectacles   the pair worn by default ("none" unless given)
//   [observer] depth_of_field   blur by the scene's depth (true / false; absent: automatic)
//   [observer] accommodation    "fixation" (the view's centre, default) or "range" (every depth
//                               within the accommodation range is sharp)
//   column "spectacles"     the pair worn in a condition, or "none"
// Cylinders are written in minus-cylinder form unless the table says cylinder_form = "plus", in
// which case they are transposed, (S, +C, axis) -> (S + C, -C, axis + 90), the same lens.
#include <string>

#include <toml++/toml.h>

#include "core/observer_optics.h"

namespace glarelab {

class TableReader;
struct ConditionRow;

// [observer.refraction] from the [observer] table's reader (which it marks consumed), if present.
void read_observer_refraction(TableReader& observer, ObserverOptics& optics);
// Every [spectacles.NAME] table from the document root, if present.
void read_spectacles_section(TableReader& top, ObserverOptics& optics);
// [observer] spectacles: the name must be "none" or a [spectacles] table's.
void read_spectacles_worn(TableReader& observer, ObserverOptics& optics);
// [observer] depth_of_field (a boolean) and accommodation ("fixation" or "range"), if present;
// "range" with depth_of_field = false is refused at the accommodation value.
void read_depth_of_field(TableReader& observer, ObserverOptics& optics);
// The spectacles of one condition: its "spectacles" column, else [observer] spectacles; nullptr for
// "none". ConfigError at the row for a name no [spectacles] table defines.
const SpectaclesSettings* spectacles_for(const ObserverOptics& optics, const ConditionRow& row);
// The tables resolved_config_toml writes (every key explicit, cylinders in minus form).
toml::table refraction_toml(const ObserverRefractionSettings& refraction);
toml::table spectacles_section_toml(const ObserverOptics& optics);

}  // namespace glarelab
