#pragma once
// The phase the aperture is multiplied by before the FFT (Ritschel et al. 2009, Eq. 3), and the
// sampling condition that phase imposes on the aperture grid (docs/GLARE_OPTICS.md derives it).
//
// Both forms are quadratic, phi(r) = pi * c * r^2 with c in 1/m^2:
//   paper:   c = 1 / (lambda d), d = 24 mm pupil-to-retina distance (Eq. 3's E);
//   defocus: c = D / lambda, D the eye's defocus in dioptres (thin-lens focus error).
// The paper's E is therefore the same phase as a defocus of 1/d = 41.7 dioptres.
#include <numbers>
#include <string>

namespace glarelab {

enum class PhaseForm { none, defocus, paper };

// Pupil-to-retina distance d of Ritschel's Eq. 3 (section 4.1), metres.
inline constexpr double kPaperPupilRetinaDistance_m = 0.024;

PhaseForm parse_phase_form(const std::string& name);  // "none" | "defocus" | "paper"; throws std::invalid_argument
const char* phase_form_name(PhaseForm form);

// Quadratic phase coefficient c (1/m^2) of phi = pi c r^2 for a form; 0 for none.
double phase_coefficient_per_m2(PhaseForm form, double wavelength_nm, double defocus_dioptres);

// Phase (radians) at squared radius r2_m2 (m^2).
inline double quadratic_phase_rad(double coefficient_per_m2, double r2_m2) {
  return std::numbers::pi * coefficient_per_m2 * r2_m2;
}

struct PhaseSamplingReport {
  double max_phase_step_rad = 0.0;   // largest phase change between neighbouring samples inside the pupil
  double max_pixel_mm = 0.0;         // largest sample spacing with steps < pi (infinite for no phase)
  // Smallest N with dx = aperture_width / N below max_pixel_mm, computed in double (a huge defocus
  // needs more than any integer holds) and saturated at the largest long long.
  long long required_grid_px = 0;
  double required_grid_px_exact = 0.0;  // the same, unsaturated (may exceed 2^63)
  bool aliased = false;              // max_phase_step_rad >= pi
  std::string warning;               // empty unless aliased: names the numbers
};

// Sampling check for phi = pi c r^2 on a grid of pixel size pixel_mm over a pupil of radius
// pupil_radius_mm (the phase only matters where the aperture transmits). The phase gradient is
// 2 pi c r, largest at the pupil edge; a step below pi per sample (Nyquist for the local spatial
// frequency c r) needs pixel < 1 / (2 c r_max).
PhaseSamplingReport check_phase_sampling(double coefficient_per_m2, double pupil_radius_mm, double pixel_mm,
                                         double aperture_width_mm);

// The largest |defocus| (dioptres) a grid of pixel pixel_mm samples over a pupil of radius
// pupil_radius_mm at wavelength_nm: the sampling condition above, pixel < 1 / (2 c r) with
// c = D / lambda, solved for D: |D| < lambda / (2 r dx).
double max_sampled_defocus_dioptres(double wavelength_nm, double pupil_radius_mm, double pixel_mm);

}  // namespace glarelab
