#include "glare/eye/eye_parameters.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/errors.h"

namespace glarelab {

GlareMode parse_glare_mode(const std::string& name) {
  if (name == "dynamic") return GlareMode::dynamic;
  if (name == "static") return GlareMode::static_eye;
  if (name == "control") return GlareMode::control;
  throw ConfigError(SourceLocation{"glare mode", 0, 0}, "mode",
                    "unknown glare mode '" + name + "' (expected dynamic, static or control)");
}

std::string to_string(GlareMode mode) {
  switch (mode) {
    case GlareMode::dynamic: return "dynamic";
    case GlareMode::static_eye: return "static";
    case GlareMode::control: return "control";
  }
  return "dynamic";
}

namespace {

class Checker {
 public:
  explicit Checker(const std::string& origin) : where_{origin, 0, 0} {}

  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    throw ConfigError(where_, key, message);
  }
  void finite(const std::string& key, double value) const {
    if (!std::isfinite(value)) fail(key, "must be a finite number, got " + text(value));
  }
  void positive(const std::string& key, double value) const {
    finite(key, value);
    if (!(value > 0.0)) fail(key, "must be > 0, got " + text(value));
  }
  void non_negative(const std::string& key, double value) const {
    finite(key, value);
    if (value < 0.0) fail(key, "must be >= 0, got " + text(value));
  }
  void in_range(const std::string& key, double value, double low, double high) const {
    finite(key, value);
    if (value < low || value > high)
      fail(key, "must lie in [" + text(low) + ", " + text(high) + "], got " + text(value));
  }
  void count(const std::string& key, int value, int low, int high) const {
    if (value < low || value > high)
      fail(key, "must be an integer in [" + std::to_string(low) + ", " + std::to_string(high) + "], got " +
                    std::to_string(value));
  }
  static std::string text(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
  }

 private:
  SourceLocation where_;
};

}  // namespace

void validate(const EyeParameters& p, const std::string& origin) {
  const Checker c(origin);
  c.non_negative("static_time_s", p.static_time_s);
  if (p.static_time_s > kMaxEyeModelTime_s)
    c.fail("static_time_s", std::string("must be at most ") + kMaxEyeModelTimeText + ", got " +
                                Checker::text(p.static_time_s) + " s");

  c.in_range("pupil_max_diameter_mm", p.pupil_max_diameter_mm, 1.0, 12.0);
  c.in_range("pupil_min_diameter_mm", p.pupil_min_diameter_mm, 0.5, 12.0);
  if (p.pupil_min_diameter_mm >= p.pupil_max_diameter_mm)
    c.fail("pupil_min_diameter_mm", "must be smaller than pupil_max_diameter_mm (" +
                                        Checker::text(p.pupil_max_diameter_mm) + ")");
  // Eq. 1 needs p < p_max for the square root; Eq. 2 reaches 7.9 mm in the dark.
  if (p.pupil_max_diameter_mm <= 7.9)
    c.fail("pupil_max_diameter_mm", "must exceed 7.9 mm, the largest mean pupil of Eq. 2 (Moon and Spencer)");
  c.in_range("hippus_noise_amplitude", p.hippus_noise_amplitude, 0.0, 1.0);
  c.positive("initial_field_luminance_cd_m2", p.initial_field_luminance_cd_m2);
  c.positive("field_luminance_rod_time_constant_s", p.field_luminance_rod_time_constant_s);
  c.positive("field_luminance_cone_time_constant_s", p.field_luminance_cone_time_constant_s);
  c.positive("field_luminance_rod_half_sensitivity_cd_m2", p.field_luminance_rod_half_sensitivity_cd_m2);

  c.in_range("accommodative_demand_dioptres", p.accommodative_demand_dioptres, 0.0, 20.0);
  c.non_negative("accommodation_low_frequency_rms_dioptres_per_mm", p.accommodation_low_frequency_rms_dioptres_per_mm);
  c.positive("accommodation_low_frequency_max_hz", p.accommodation_low_frequency_max_hz);
  c.positive("accommodation_high_frequency_centre_hz", p.accommodation_high_frequency_centre_hz);
  c.non_negative("accommodation_high_frequency_half_width_hz", p.accommodation_high_frequency_half_width_hz);
  if (p.accommodation_high_frequency_half_width_hz >= p.accommodation_high_frequency_centre_hz)
    c.fail("accommodation_high_frequency_half_width_hz", "must be smaller than the centre frequency");
  c.non_negative("accommodation_high_frequency_rms_dioptres", p.accommodation_high_frequency_rms_dioptres);

  c.count("lens_particle_count", p.lens_particle_count, 0, 100000);
  c.positive("lens_equatorial_radius_mm", p.lens_equatorial_radius_mm);
  c.positive("lens_thickness_mm", p.lens_thickness_mm);
  c.positive("lens_particle_diameter_min_mm", p.lens_particle_diameter_min_mm);
  c.positive("lens_particle_diameter_max_mm", p.lens_particle_diameter_max_mm);
  if (p.lens_particle_diameter_min_mm > p.lens_particle_diameter_max_mm)
    c.fail("lens_particle_diameter_min_mm", "must not exceed lens_particle_diameter_max_mm");
  c.count("lens_deformation_grid_nodes", p.lens_deformation_grid_nodes, 3, 129);
  c.finite("lens_equator_displacement_mm_per_dioptre", p.lens_equator_displacement_mm_per_dioptre);
  c.count("lens_grating_count", p.lens_grating_count, 0, 100000);
  c.count("lens_grating_lines_per_grating", p.lens_grating_lines_per_grating, 1, 1000);
  c.positive("lens_grating_period_mm", p.lens_grating_period_mm);
  c.in_range("lens_grating_line_width_fraction", p.lens_grating_line_width_fraction, 1e-6, 1.0);
  c.in_range("lens_grating_transmittance", p.lens_grating_transmittance, 0.0, 1.0);
  c.positive("lens_grating_length_mm", p.lens_grating_length_mm);
  c.non_negative("lens_cortex_inner_radius_mm", p.lens_cortex_inner_radius_mm);
  const double grating_half_width_mm = 0.5 * p.lens_grating_lines_per_grating * p.lens_grating_period_mm;
  const double annulus_outer_mm =
      std::sqrt(std::max(0.0, p.lens_equatorial_radius_mm * p.lens_equatorial_radius_mm -
                                  grating_half_width_mm * grating_half_width_mm));
  if (p.lens_grating_count > 0 && p.lens_cortex_inner_radius_mm + p.lens_grating_length_mm > annulus_outer_mm)
    c.fail("lens_grating_length_mm", "a grating of this length does not fit in the cortex annulus [" +
                                         Checker::text(p.lens_cortex_inner_radius_mm) + ", " +
                                         Checker::text(p.lens_equatorial_radius_mm) + "] mm");

  c.count("vitreous_particle_count", p.vitreous_particle_count, 0, 100000);
  c.positive("vitreous_particle_diameter_mm", p.vitreous_particle_diameter_mm);
  c.positive("vitreous_sampling_radius_mm", p.vitreous_sampling_radius_mm);
  c.non_negative("vitreous_front_depth_mm", p.vitreous_front_depth_mm);
  c.finite("vitreous_back_depth_mm", p.vitreous_back_depth_mm);
  if (p.vitreous_back_depth_mm <= p.vitreous_front_depth_mm)
    c.fail("vitreous_back_depth_mm", "must be larger than vitreous_front_depth_mm");
  c.finite("eye_rotation_centre_depth_mm", p.eye_rotation_centre_depth_mm);
  c.positive("vitreous_natural_frequency_hz", p.vitreous_natural_frequency_hz);
  c.positive("vitreous_damping_ratio", p.vitreous_damping_ratio);
  c.positive("vitreous_time_step_s", p.vitreous_time_step_s);
  // Forward Euler on theta'' = -w0^2 theta - 2 zeta w0 theta' is stable and accurate to ~1% only when
  // the step is small against the fastest time scale, 1 / (w0 (zeta + sqrt(zeta^2 - 1))).
  const double omega0 = 2.0 * 3.14159265358979323846 * p.vitreous_natural_frequency_hz;
  const double zeta = p.vitreous_damping_ratio;
  const double fastest_rate = omega0 * (zeta + std::sqrt(std::max(0.0, zeta * zeta - 1.0)) + 1.0);
  if (p.vitreous_time_step_s * fastest_rate > 0.05)
    c.fail("vitreous_time_step_s", "too large for forward Euler: must be <= " +
                                       Checker::text(0.05 / fastest_rate) + " s for these vitreous dynamics");
  c.positive("saccade_mean_interval_s", p.saccade_mean_interval_s);
  c.non_negative("saccade_impulse_sd_rad_s", p.saccade_impulse_sd_rad_s);
  c.positive("saccade_force_decay_s", p.saccade_force_decay_s);

  c.count("cornea_particle_count", p.cornea_particle_count, 0, 100000);
  c.positive("cornea_particle_diameter_mm", p.cornea_particle_diameter_mm);
  c.count("retina_particle_count", p.retina_particle_count, 0, 100000);
  c.positive("retina_particle_diameter_mm", p.retina_particle_diameter_mm);
  c.positive("static_particle_region_radius_mm", p.static_particle_region_radius_mm);

  c.positive("blink_closing_duration_s", p.blink_closing_duration_s);
  c.non_negative("blink_closed_duration_s", p.blink_closed_duration_s);
  c.positive("blink_opening_duration_s", p.blink_opening_duration_s);
  const double blink_duration_s = p.blink_closing_duration_s + p.blink_closed_duration_s + p.blink_opening_duration_s;
  c.finite("blink_mean_interval_s", p.blink_mean_interval_s);
  if (p.blink_mean_interval_s <= blink_duration_s)
    c.fail("blink_mean_interval_s", "must be longer than one blink (" + Checker::text(blink_duration_s) + " s)");
  c.in_range("squint_closure", p.squint_closure, 0.0, 1.0);
  c.finite("upper_lid_open_margin_mm", p.upper_lid_open_margin_mm);
  c.finite("lower_lid_open_margin_mm", p.lower_lid_open_margin_mm);
  c.finite("lid_meeting_height_mm", p.lid_meeting_height_mm);
  if (!(p.lower_lid_open_margin_mm < p.lid_meeting_height_mm && p.lid_meeting_height_mm < p.upper_lid_open_margin_mm))
    c.fail("lid_meeting_height_mm", "must lie between lower_lid_open_margin_mm and upper_lid_open_margin_mm");
  c.positive("lid_margin_curvature_radius_mm", p.lid_margin_curvature_radius_mm);
  c.count("upper_eyelash_count", p.upper_eyelash_count, 0, 10000);
  c.count("lower_eyelash_count", p.lower_eyelash_count, 0, 10000);
  c.positive("eyelash_width_mm", p.eyelash_width_mm);
  c.non_negative("upper_eyelash_overhang_max_mm", p.upper_eyelash_overhang_max_mm);
  c.non_negative("lower_eyelash_overhang_max_mm", p.lower_eyelash_overhang_max_mm);
  c.positive("eyelash_window_half_width_mm", p.eyelash_window_half_width_mm);
}

}  // namespace glarelab
