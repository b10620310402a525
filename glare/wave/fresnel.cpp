#include "glare/wave/fresnel.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace glarelab {

PhaseForm parse_phase_form(const std::string& name) {
  if (name == "none") return PhaseForm::none;
  if (name == "defocus") return PhaseForm::defocus;
  if (name == "paper") return PhaseForm::paper;
  throw std::invalid_argument("glare/wave/fresnel: unknown phase form '" + name + "' (none, defocus, paper)");
}

const char* phase_form_name(PhaseForm form) {
  switch (form) {
    case PhaseForm::none: return "none";
    case PhaseForm::defocus: return "defocus";
    case PhaseForm::paper: return "paper";
  }
  return "none";
}

double phase_coefficient_per_m2(PhaseForm form, double wavelength_nm, double defocus_dioptres) {
  const double wavelength_m = wavelength_nm * 1e-9;
  switch (form) {
    case PhaseForm::none: return 0.0;
    // Thin-lens focus error of D dioptres: path difference D r^2 / 2, phase k D r^2 / 2 = pi D r^2 / lambda.
    case PhaseForm::defocus: return defocus_dioptres / wavelength_m;
    // Ritschel et al. 2009, Eq. 3: E = exp(i pi (x^2 + y^2) / (lambda d)).
    case PhaseForm::paper: return 1.0 / (wavelength_m * kPaperPupilRetinaDistance_m);
  }
  return 0.0;
}

PhaseSamplingReport check_phase_sampling(double coefficient_per_m2, double pupil_radius_mm, double pixel_mm,
                                         double aperture_width_mm) {
  PhaseSamplingReport report;
  const double c = std::abs(coefficient_per_m2);
  const double r_max_m = pupil_radius_mm * 1e-3;
  const double dx_m = pixel_mm * 1e-3;
  if (c == 0.0 || r_max_m <= 0.0) {
    report.max_pixel_mm = std::numeric_limits<double>::infinity();
    report.required_grid_px = 1;
    report.required_grid_px_exact = 1.0;
    return report;
  }
  // Exact step between the edge sample and its inward neighbour: pi c (r^2 - (r - dx)^2).
  report.max_phase_step_rad = std::numbers::pi * c * (2.0 * r_max_m * dx_m - dx_m * dx_m);
  if (dx_m >= r_max_m) report.max_phase_step_rad = std::numbers::pi * c * r_max_m * r_max_m;
  report.max_pixel_mm = 1e3 / (2.0 * c * r_max_m);
  // In double first: for a defocus of 1e30 D the grid would be ~7e31 px, past any integer type.
  report.required_grid_px_exact = std::ceil(aperture_width_mm / report.max_pixel_mm);
  constexpr double kLongLongLimit = 0x1p63;  // 2^63, the first double past the largest long long
  report.required_grid_px = report.required_grid_px_exact < kLongLongLimit
                                ? static_cast<long long>(report.required_grid_px_exact)
                                : std::numeric_limits<long long>::max();
  report.aliased = report.max_phase_step_rad >= std::numbers::pi;
  if (report.aliased) {
    std::ostringstream message;
    message << "glare/wave/fresnel: quadratic phase aliased: " << report.max_phase_step_rad
            << " rad per sample at the pupil edge (r = " << pupil_radius_mm << " mm, dx = " << pixel_mm * 1e3
            << " um); needs dx < " << report.max_pixel_mm * 1e3 << " um, i.e. a grid of at least "
            << std::setprecision(15) << report.required_grid_px_exact << std::setprecision(6) << " px over " << aperture_width_mm << " mm";
    report.warning = message.str();
  }
  return report;
}

double max_sampled_defocus_dioptres(double wavelength_nm, double pupil_radius_mm, double pixel_mm) {
  return (wavelength_nm * 1e-9) / (2.0 * (pupil_radius_mm * 1e-3) * (pixel_mm * 1e-3));
}

}  // namespace glarelab
