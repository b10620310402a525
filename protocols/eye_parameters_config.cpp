// [glare.eye]: the eye model's parameters, read strictly through TableReader. Each key is one field
// of EyeParameters with bounds (protocols/eye_parameters_config.h); the table below is the one list
// the reader, the resolved configuration and the tests walk, so no key can be read and not written
// back, or written and not read.
#include "protocols/eye_parameters_config.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "core/errors.h"
#include "core/number_text.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {
namespace {

using P = EyeParameters;

constexpr EyeParameterKey number(std::string_view key, double P::*field, double minimum, double maximum,
                                 bool minimum_excluded, std::string_view unit) {
  return EyeParameterKey{key, field, nullptr, minimum, maximum, minimum_excluded, unit};
}
constexpr EyeParameterKey count(std::string_view key, int P::*field, int minimum, int maximum) {
  return EyeParameterKey{key, nullptr, field, double(minimum), double(maximum), false, ""};
}
// Whether the minimum itself is allowed.
constexpr bool open = true, closed = false;

// Bounds. Diameters of scatterers stop at 1 mm (a particle that size is an opacity, not the eye's
// scatter); counts at 100000 (the glare engine rasterises each one every frame); lengths inside the
// eye at its ~24 mm axial length or its 12 mm cornea; times at what a session can see (an hour
// between blinks is "never"). Where glare/eye/eye_parameters.cpp's validate() states a bound, it is
// the same one here: pupil_max_diameter_mm above Eq. 2's 7.9 mm, the counts' ranges, the
// transmittances and fractions in [0, 1].
constexpr std::array kKeys = {
    // --- Pupil and hippus (Ritschel section 3.2, Eqs. 1 and 2) ---
    number("pupil_max_diameter_mm", &P::pupil_max_diameter_mm, 7.9, 12.0, open, "mm"),
    number("pupil_min_diameter_mm", &P::pupil_min_diameter_mm, 0.5, 7.9, closed, "mm"),
    number("hippus_noise_amplitude", &P::hippus_noise_amplitude, 0.0, 1.0, closed, ""),
    number("field_luminance_rod_time_constant_s", &P::field_luminance_rod_time_constant_s, 0.0, 60.0, open, "s"),
    number("field_luminance_cone_time_constant_s", &P::field_luminance_cone_time_constant_s, 0.0, 60.0, open, "s"),
    number("field_luminance_rod_half_sensitivity_cd_m2", &P::field_luminance_rod_half_sensitivity_cd_m2, 0.0, 1e4,
           open, "cd/m2"),
    // --- Accommodation microfluctuations (section 3.3) ---
    number("accommodative_demand_dioptres", &P::accommodative_demand_dioptres, 0.0, 20.0, closed, "D"),
    number("accommodation_low_frequency_rms_dioptres_per_mm", &P::accommodation_low_frequency_rms_dioptres_per_mm, 0.0,
           1.0, closed, "D/mm"),
    number("accommodation_low_frequency_max_hz", &P::accommodation_low_frequency_max_hz, 0.0, 10.0, open, "Hz"),
    number("accommodation_high_frequency_centre_hz", &P::accommodation_high_frequency_centre_hz, 0.0, 20.0, open, "Hz"),
    number("accommodation_high_frequency_half_width_hz", &P::accommodation_high_frequency_half_width_hz, 0.0, 20.0,
           closed, "Hz"),
    number("accommodation_high_frequency_rms_dioptres", &P::accommodation_high_frequency_rms_dioptres, 0.0, 2.0, closed,
           "D"),
    // --- Lens (section 3.3) ---
    count("lens_particle_count", &P::lens_particle_count, 0, 100000),
    number("lens_equatorial_radius_mm", &P::lens_equatorial_radius_mm, 0.0, 10.0, open, "mm"),
    number("lens_thickness_mm", &P::lens_thickness_mm, 0.0, 10.0, open, "mm"),
    number("lens_particle_diameter_min_mm", &P::lens_particle_diameter_min_mm, 0.0, 1.0, open, "mm"),
    number("lens_particle_diameter_max_mm", &P::lens_particle_diameter_max_mm, 0.0, 1.0, open, "mm"),
    count("lens_deformation_grid_nodes", &P::lens_deformation_grid_nodes, 3, 129),
    number("lens_equator_displacement_mm_per_dioptre", &P::lens_equator_displacement_mm_per_dioptre, 0.0, 1.0, closed,
           "mm/D"),
    count("lens_grating_count", &P::lens_grating_count, 0, 100000),
    count("lens_grating_lines_per_grating", &P::lens_grating_lines_per_grating, 1, 1000),
    number("lens_grating_period_mm", &P::lens_grating_period_mm, 0.0, 1.0, open, "mm"),
    number("lens_grating_line_width_fraction", &P::lens_grating_line_width_fraction, 0.0, 1.0, open, ""),
    number("lens_grating_transmittance", &P::lens_grating_transmittance, 0.0, 1.0, closed, ""),
    number("lens_grating_length_mm", &P::lens_grating_length_mm, 0.0, 10.0, open, "mm"),
    number("lens_cortex_inner_radius_mm", &P::lens_cortex_inner_radius_mm, 0.0, 10.0, closed, "mm"),
    // --- Vitreous (section 3.4) ---
    count("vitreous_particle_count", &P::vitreous_particle_count, 0, 100000),
    number("vitreous_particle_diameter_mm", &P::vitreous_particle_diameter_mm, 0.0, 1.0, open, "mm"),
    number("vitreous_sampling_radius_mm", &P::vitreous_sampling_radius_mm, 0.0, 12.0, open, "mm"),
    number("vitreous_front_depth_mm", &P::vitreous_front_depth_mm, 0.0, 24.0, closed, "mm"),
    number("vitreous_back_depth_mm", &P::vitreous_back_depth_mm, 0.0, 24.0, open, "mm"),
    number("eye_rotation_centre_depth_mm", &P::eye_rotation_centre_depth_mm, 0.0, 24.0, closed, "mm"),
    number("vitreous_natural_frequency_hz", &P::vitreous_natural_frequency_hz, 0.0, 100.0, open, "Hz"),
    number("vitreous_damping_ratio", &P::vitreous_damping_ratio, 0.0, 100.0, open, ""),
    number("vitreous_time_step_s", &P::vitreous_time_step_s, 0.0, 0.1, open, "s"),
    number("saccade_mean_interval_s", &P::saccade_mean_interval_s, 0.0, 3600.0, open, "s"),
    number("saccade_impulse_sd_rad_s", &P::saccade_impulse_sd_rad_s, 0.0, 10.0, closed, "rad/s"),
    number("saccade_force_decay_s", &P::saccade_force_decay_s, 0.0, 1.0, open, "s"),
    // --- Cornea and retina (sections 3.1, 3.5) ---
    count("cornea_particle_count", &P::cornea_particle_count, 0, 100000),
    number("cornea_particle_diameter_mm", &P::cornea_particle_diameter_mm, 0.0, 1.0, open, "mm"),
    count("retina_particle_count", &P::retina_particle_count, 0, 100000),
    number("retina_particle_diameter_mm", &P::retina_particle_diameter_mm, 0.0, 1.0, open, "mm"),
    number("static_particle_region_radius_mm", &P::static_particle_region_radius_mm, 0.0, 12.0, open, "mm"),
    // --- Eyelids and eyelashes (section 3.6) ---
    number("blink_mean_interval_s", &P::blink_mean_interval_s, 0.0, 3600.0, open, "s"),
    number("blink_closing_duration_s", &P::blink_closing_duration_s, 0.0, 2.0, open, "s"),
    number("blink_closed_duration_s", &P::blink_closed_duration_s, 0.0, 10.0, closed, "s"),
    number("blink_opening_duration_s", &P::blink_opening_duration_s, 0.0, 2.0, open, "s"),
    number("squint_closure", &P::squint_closure, 0.0, 1.0, closed, ""),
    number("upper_lid_open_margin_mm", &P::upper_lid_open_margin_mm, -12.0, 12.0, closed, "mm"),
    number("lower_lid_open_margin_mm", &P::lower_lid_open_margin_mm, -12.0, 12.0, closed, "mm"),
    number("lid_meeting_height_mm", &P::lid_meeting_height_mm, -12.0, 12.0, closed, "mm"),
    number("lid_margin_curvature_radius_mm", &P::lid_margin_curvature_radius_mm, 0.0, 1000.0, open, "mm"),
    count("upper_eyelash_count", &P::upper_eyelash_count, 0, 10000),
    count("lower_eyelash_count", &P::lower_eyelash_count, 0, 10000),
    number("eyelash_width_mm", &P::eyelash_width_mm, 0.0, 1.0, open, "mm"),
    number("upper_eyelash_overhang_max_mm", &P::upper_eyelash_overhang_max_mm, 0.0, 12.0, closed, "mm"),
    number("lower_eyelash_overhang_max_mm", &P::lower_eyelash_overhang_max_mm, 0.0, 12.0, closed, "mm"),
    number("eyelash_window_half_width_mm", &P::eyelash_window_half_width_mm, 0.0, 20.0, open, "mm"),
};

std::string bounds_text(const EyeParameterKey& key) {
  const std::string unit = key.unit.empty() ? "" : " " + std::string(key.unit);
  if (key.count != nullptr)
    return "from " + number_text(static_cast<std::int64_t>(key.minimum)) + " to " +
           number_text(static_cast<std::int64_t>(key.maximum));
  if (key.minimum_excluded) return "> " + number_text(key.minimum) + " and at most " + number_text(key.maximum) + unit;
  return "from " + number_text(key.minimum) + " to " + number_text(key.maximum) + unit;
}

void read_key(TableReader& reader, const EyeParameterKey& key, EyeParameters& parameters) {
  if (key.count != nullptr) {
    const std::optional<std::int64_t> value = reader.integer(key.key);
    if (!value) return;
    if (static_cast<double>(*value) < key.minimum || static_cast<double>(*value) > key.maximum)
      reader.fail(key.key, "must be an integer " + bounds_text(key) + ", found " + number_text(*value));
    parameters.*key.count = static_cast<int>(*value);
    return;
  }
  const std::optional<double> value = reader.number(key.key);
  if (!value) return;
  const bool above = key.minimum_excluded ? *value > key.minimum : *value >= key.minimum;
  if (!above || *value > key.maximum) reader.fail(key.key, "must be " + bounds_text(key) + ", found " + number_text(*value));
  parameters.*key.number = *value;
}

}  // namespace

std::span<const EyeParameterKey> eye_parameter_keys() { return kKeys; }

void read_glare_eye(TableReader& glare, EyeParameters& parameters) {
  const toml::table* table = glare.table("eye");
  if (table == nullptr) return;
  TableReader reader(*table, glare.key_path("eye"), glare.file());
  for (const EyeParameterKey& key : kKeys) read_key(reader, key, parameters);
  reader.report_unused();
  // The rules between fields (glare/eye/eye_parameters.cpp), at the value of the key they name.
  try {
    validate(parameters, reader.key_path(""));
  } catch (const ConfigError& error) {
    reader.fail(error.key(), error.message());
  }
}

toml::table glare_eye_toml(const EyeParameters& parameters) {
  toml::table table;
  for (const EyeParameterKey& key : kKeys) {
    if (key.count != nullptr)
      table.insert(key.key, static_cast<std::int64_t>(parameters.*key.count));
    else
      table.insert(key.key, parameters.*key.number);
  }
  return table;
}

}  // namespace glarelab
