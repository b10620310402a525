#pragma once
// Every parameter of the dynamic eye model (Ritschel et al. 2009, sections 3-4), with units in the
// names and the paper's value as default where the paper gives one. Where it does not, the default
// is derived from the physiology cited beside it; docs/EYE_MODEL.md lists each one with its source.
//
// Names are the experiment-file keys: validate() reports a bad value as a ConfigError naming the key.
#include <string>

namespace glarelab {

// dynamic: the eye moves (pupil, lens, vitreous, lids). static: the same eye frozen at
// static_time_s, identical geometry at every time. control: no glare at all (the aperture is
// flagged glare_enabled = false and carries no scatterers; the image passes through unchanged).
enum class GlareMode { dynamic, static_eye, control };

// The latest time the eye model answers for (static_time_s, session times, `psf --time-s`,
// `render --time`, `eye-trace --duration-s` and `--static-time-s`): 24 h. A psychophysics session
// lasts minutes to a few hours (people tire long before a day), and static_time_s is an instant
// within a viewing, so no real study comes near it; a larger value is a
// mistake (a time in ms or ns, a stray exponent) and is refused where it is given. The model's cost
// does not grow with the time (glare/eye/vitreous_model.h), but its inputs are kept where 1 ms steps and the
// noise lattices stay far inside 64-bit integers and double precision (2^-36 s resolution at 24 h).
inline constexpr double kMaxEyeModelTime_s = 86400.0;
inline constexpr const char* kMaxEyeModelTimeText = "86400 s (24 h)";

GlareMode parse_glare_mode(const std::string& name);  // "dynamic", "static", "control"; ConfigError otherwise
std::string to_string(GlareMode mode);

struct EyeParameters {
  GlareMode mode = GlareMode::dynamic;
  double static_time_s = 0.0;  // the instant a static eye is frozen at

  // --- Pupil and hippus (section 3.2, Eqs. 1 and 2) ---
  double pupil_max_diameter_mm = 9.0;  // p_max of Eq. 1 (paper: 9 mm); also the upper clamp
  // Lower clamp of the simulated pupil. Eq. 2 alone never goes below 1.9 mm; hippus can. 1.5 mm is the
  // smallest pupil the glare engine must handle, a little under the ~2 mm physiological
  // minimum of Luidolt 2020 section 2.1.3 ("approximately 2 to 8 mm").
  double pupil_min_diameter_mm = 1.5;
  // Scale of noise() in Eq. 1 (noise is three-octave value noise in [-1, 1]). The paper does not state
  // it; 0.1 gives a standard deviation of ~0.16 mm (peak-to-peak ~0.6 mm) at the brightest fields,
  // the size of pupillary unrest, and keeps Eq. 1's mean on Eq. 2.
  double hippus_noise_amplitude = 0.1;
  // Field luminance before any frame was shown (and for a constant field).
  double initial_field_luminance_cd_m2 = 100.0;
  // Time-damped field luminance (Ritschel 3.2 after Durand and Dorsey 2000), first order, with the
  // luminance-dependent time constant of Luidolt 2020 Eqs. 5.2-5.4 (after Krawczyk et al. 2005):
  // tau(Y) = sigma(Y) tau_rod + (1 - sigma(Y)) tau_cone, sigma(Y) = Y_half / (Y_half + Y).
  double field_luminance_rod_time_constant_s = 0.4;
  double field_luminance_cone_time_constant_s = 0.1;
  double field_luminance_rod_half_sensitivity_cd_m2 = 0.04;

  // --- Accommodation microfluctuations (section 3.3, after Gray, Winn and Gilmartin 1993) ---
  // Mean accommodation: the display at 0.6 m (the README's example viewing distance).
  double accommodative_demand_dioptres = 1.0 / 0.6;
  // Low-frequency component (< 0.6 Hz): RMS grows in proportion to the Eq. 2 pupil diameter
  // (Ritschel: "more pronounced for larger size"); 0.02 D/mm gives 0.04-0.16 D RMS over 2-8 mm.
  double accommodation_low_frequency_rms_dioptres_per_mm = 0.02;
  double accommodation_low_frequency_max_hz = 0.6;
  // High-frequency component: narrow band 1.3-2.1 Hz (centre 1.7 Hz, half-width 0.4 Hz).
  double accommodation_high_frequency_centre_hz = 1.7;
  double accommodation_high_frequency_half_width_hz = 0.4;
  double accommodation_high_frequency_rms_dioptres = 0.04;

  // --- Lens (section 3.3) ---
  int lens_particle_count = 750;              // paper: 750 particles
  double lens_equatorial_radius_mm = 4.5;     // adult lens, ~9 mm equatorial diameter
  double lens_thickness_mm = 4.0;             // axial thickness, ~4 mm
  // Particles of varying size: diameters uniform in [min, max]. Their Airy discs (1.22 lambda / d)
  // then span ~2-8 degrees at 568 nm, the extent of the ciliary corona's needles.
  double lens_particle_diameter_min_mm = 0.005;
  double lens_particle_diameter_max_mm = 0.020;
  int lens_deformation_grid_nodes = 17;       // paper: 17 x 17 mass-spring grid
  // Radial displacement of the lens equator per dioptre of accommodation (the ciliary driver element);
  // the equator moves inwards as accommodation rises.
  double lens_equator_displacement_mm_per_dioptre = 0.03;
  int lens_grating_count = 200;               // paper: 200 gratings
  // Each grating is a patch of parallel fibre membranes. The lenticular halo has a width of 0.35 deg
  // at a 3 deg radius (Mellerio and Palmer, in Spencer 1995 section 3.1.1): K periods give an angular
  // FWHM of ~0.886 lambda / (K e) = 0.886 * 3 deg / K, so K = 0.886 * 3 / 0.35 = 7.6 -> 8 lines.
  int lens_grating_lines_per_grating = 8;
  // Fibre spacing e = lambda / sin(theta) (Spencer 1995 Eq. 4) with the halo at theta = 3 deg for
  // lambda = 568 nm: e = 0.568 um / sin(3 deg) = 10.85 um.
  double lens_grating_period_mm = 0.000568 / 0.052335956242943835;
  double lens_grating_line_width_fraction = 0.5;  // membrane width / period (first order maximal)
  double lens_grating_transmittance = 0.5;        // fibre membranes are weak scatterers, not opaque
  double lens_grating_length_mm = 0.6;            // radial length of one patch
  // The clear central lens: a beam under 3 mm passes without meeting the grating (Simpson, in
  // Spencer 1995 section 2.1), so the cortex annulus starts at a 1.5 mm radius.
  double lens_cortex_inner_radius_mm = 1.5;

  // --- Vitreous (section 3.4) ---
  // Counts and sizes: Table 1 gives the vitreous 10% of the scattering against the lens's 40%; for
  // opaque discs the diffracted power is proportional to the blocked area (Babinet), so the vitreous
  // blocks 1/4 of the lens particles' area (0.103 mm2): 82 particles of 20 um inside the 9 mm disc,
  // 122 in the 5.5 mm sampling cylinder (which covers the disc at every angle).
  int vitreous_particle_count = 122;
  double vitreous_particle_diameter_mm = 0.020;  // comparable to the larger lens nucleus particles
  double vitreous_sampling_radius_mm = 5.5;
  double vitreous_front_depth_mm = 4.0;          // behind the pupil plane (back of the lens)
  double vitreous_back_depth_mm = 20.5;          // the retina is ~24 mm behind the cornea
  double eye_rotation_centre_depth_mm = 10.0;    // centre of rotation, ~13 mm behind the cornea
  // Damped rotation: theta'' = -w0^2 theta - 2 zeta w0 theta' + saccade torques. Zimmerman 1980
  // found the human vitreous overdamped (zeta > 1) and slow; zeta = 1.5 with f0 = 0.5 Hz gives a slow
  // relaxation time of 0.83 s and a fast one of 0.12 s.
  double vitreous_natural_frequency_hz = 0.5;
  double vitreous_damping_ratio = 1.5;
  double vitreous_time_step_s = 0.001;       // forward Euler step, fixed, from t = 0
  double saccade_mean_interval_s = 0.5;      // ~2 saccades per second while viewing a scene
  double saccade_impulse_sd_rad_s = 0.1;     // angular velocity given to the vitreous (normal, sd)
  double saccade_force_decay_s = 0.02;       // damped force: J / tau exp(-t / tau), saccades last 20-100 ms

  // --- Cornea and retina (sections 3.1, 3.5) ---
  // Cornea: flat cells of 15 um diameter (Ritschel 3.1), static and sparse. Table 1 ratio 27.5:40 to
  // the lens area (0.103 mm2) -> 0.0709 mm2 / (pi/4 * 0.015^2) = 401 cells in the 9 mm disc.
  int cornea_particle_count = 401;
  double cornea_particle_diameter_mm = 0.015;
  // Retina: "fewer and larger particles" (3.5). Table 1 ratio 20:40 -> 0.0516 mm2 = 41 discs of 40 um.
  int retina_particle_count = 41;
  double retina_particle_diameter_mm = 0.040;
  double static_particle_region_radius_mm = 4.5;  // cornea and retina particles lie in the 9 mm disc

  // --- Eyelids and eyelashes (section 3.6) ---
  double blink_mean_interval_s = 60.0 / 17.0;  // 17 blinks per minute at rest (Bentivoglio et al. 1997)
  // Blink kinematics: a fast down phase and a slower up phase (VanderWerf et al. 2003): ~100 ms
  // closing, a short closed phase, ~200 ms opening; a blink lasts ~0.35 s.
  double blink_closing_duration_s = 0.1;
  double blink_closed_duration_s = 0.05;
  double blink_opening_duration_s = 0.2;
  double squint_closure = 0.0;  // constant lid closure, 0..1 (Ritschel 3.6: squinting against glare)
  double upper_lid_open_margin_mm = 4.5;    // upper lid covers the top ~1.3 mm of the 11.6 mm cornea
  double lower_lid_open_margin_mm = -5.5;   // lower lid at the lower limbus
  double lid_meeting_height_mm = -3.5;      // where the lids meet when closed (the upper lid does most of the work)
  double lid_margin_curvature_radius_mm = 25.0;  // parabola through a 30 mm x 10 mm palpebral fissure
  int upper_eyelash_count = 50;     // within 6 mm of the axis (~100-150 lashes over a 30 mm lid)
  int lower_eyelash_count = 25;
  double eyelash_width_mm = 0.1;
  double upper_eyelash_overhang_max_mm = 1.0;  // projected reach of a lash below the upper margin
  double lower_eyelash_overhang_max_mm = 0.5;
  double eyelash_window_half_width_mm = 6.0;   // lashes farther out cannot reach the 9 mm aperture
};

// Throws ConfigError(origin, key, message) for the first invalid value.
void validate(const EyeParameters& parameters, const std::string& origin = "eye parameters");

}  // namespace glarelab
