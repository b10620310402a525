#include "runner/cli/psf_refraction.h"

#include <cmath>
#include <iostream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "glare/refraction/astigmatic_phase.h"
#include "glare/wave/chromatic_psf.h"
#include "glare/wave/cie_cmf.h"
#include "glare/wave/fresnel.h"
#include "runner/cli/option_checks.h"

namespace glarelab::cli {

std::string psf_text(double value) {
  std::ostringstream out;
  out.precision(4);
  out << value;
  return out.str();
}

namespace {

const SourceLocation kWhere{"psf", 0, 0};
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

std::string prescription_text(const SpheroCylinder& rx) {
  return psf_text(rx.sphere_dioptres) + " / " + psf_text(rx.cylinder_dioptres) + " x " + psf_text(rx.axis_deg);
}

// The wavelengths whose phase the PSF computes, and each one's power error: one for a monochromatic
// PSF; with --spectral, Ritschel's samples with the eye's LCA (glare/wave/chromatic_psf.h).
std::vector<std::pair<double, DioptricPower>> errors_by_wavelength(const ApertureGeometry& geometry,
                                                                   const PsfOptions& options) {
  if (!options.spectral) return {{options.wavelength_nm, geometry.total_power_error()}};
  ChromaticPsfOptions chromatic;
  chromatic.reference_wavelength_nm = options.wavelength_nm;
  std::vector<std::pair<double, DioptricPower>> errors;
  for (const SpectralSample& sample : spectral_samples(options.wavelength_samples))
    errors.push_back({sample.wavelength_nm, chromatic_power_error(geometry.total_power_error(), sample.wavelength_nm, chromatic)});
  return errors;
}

}  // namespace

void read_observer_refraction(const RefractionArguments& args, bool amplitude_given, bool age_given, double age_years,
                              ObserverRefraction& refraction, ApertureGeometry& geometry) {
  const SpheroCylinder written{args.sphere_dioptres, args.cylinder_dioptres, args.axis_deg};
  const double vertex_m = 1e-3 * args.vertex_distance_mm;
  EyeRefraction eye_refraction;
  eye_refraction.correcting_prescription = minus_cylinder_form(written);
  eye_refraction.prescription_vertex_distance_m = vertex_m;
  if (args.cylinder_dioptres > 0.0)
    std::cerr << "psf: the prescription " << prescription_text(written)
              << " has a plus cylinder; taken as its minus-cylinder transposition "
              << prescription_text(eye_refraction.correcting_prescription) << "\n";
  eye_refraction.accommodation_amplitude_dioptres = amplitude_given ? args.accommodation_amplitude_dioptres
                                                    : age_given     ? hofstetter_amplitude_dioptres(age_years)
                                                                    : kSchematicAccommodationAmplitudeDioptres;
  ViewingCondition viewing;
  viewing.fixation_distance_m = args.viewing_distance_m;
  if (!args.spectacles.empty()) {
    const SpheroCylinder lens = parse_sphero_cylinder(args.spectacles);
    viewing.spectacles = ThinSpectacleLens{minus_cylinder_form(lens), vertex_m};
    if (lens.cylinder_dioptres > 0.0)
      std::cerr << "psf: --spectacles " << prescription_text(lens)
                << " has a plus cylinder; taken as its minus-cylinder transposition "
                << prescription_text(viewing.spectacles->prescription) << "\n";
    if (!(viewing.fixation_distance_m > vertex_m))
      throw ConfigError(kWhere, "--viewing-distance-m",
                        "the fixated point (" + psf_text(viewing.fixation_distance_m) +
                            " m from the cornea) must lie beyond the spectacles (" + psf_text(args.vertex_distance_mm) +
                            " mm)");
  }
  try {
    const RefractiveEye eye(eye_refraction);
    refraction.ocular_refraction = eye.ocular_refraction();
    refraction.fixation = refraction_at_fixation(eye, viewing);
  } catch (const std::invalid_argument& error) {
    throw ConfigError(kWhere, refraction.flags, error.what());
  }
  geometry.refraction_error = refraction.fixation.residual;
  const BlurEllipse blur = geometric_blur_ellipse(geometry.total_power_error(), 0.5e-3 * geometry.pupil_diameter_mm);
  std::ostringstream summary;
  summary << "psf: refraction: ocular refraction at the cornea "
          << prescription_text(refraction.ocular_refraction.prescription()) << " D, amplitude "
          << psf_text(eye_refraction.accommodation_amplitude_dioptres) << " D, accommodation "
          << psf_text(refraction.fixation.accommodation_dioptres) << " D for the point at "
          << (std::isinf(viewing.fixation_distance_m) ? std::string("infinity")
                                                      : psf_text(viewing.fixation_distance_m) + " m")
          << "; residual at the retina " << prescription_text(refraction.fixation.residual.prescription())
          << " D (positive: too much power); geometric blur " << psf_text(2.0 * blur.semi_major_rad * kDegPerRad)
          << " x " << psf_text(2.0 * blur.semi_minor_rad * kDegPerRad) << " deg, major axis at "
          << psf_text(blur.major_axis_angle_deg) << " deg from the observer's right, counterclockwise\n";
  refraction.summary = summary.str();
}

void check_refraction_sampling(const ApertureGeometry& geometry, const PsfOptions& options, const std::string& flags) {
  const double radius_mm = 0.5 * geometry.pupil_diameter_mm, width_mm = options.aperture_width_mm;
  for (const auto& [wavelength_nm, error] : errors_by_wavelength(geometry, options)) {
    const PhaseSamplingReport largest = check_power_error_sampling(error, wavelength_nm, radius_mm, width_mm / kLargestGridPx, width_mm);
    if (!largest.aliased) continue;
    const PrincipalPowers principal = principal_powers(error);
    const PhaseSamplingReport chosen =
        check_power_error_sampling(error, wavelength_nm, radius_mm, width_mm / options.grid_px, width_mm);
    throw ConfigError(kWhere, flags,
                      "the residual refraction error at the retina, principal powers " + psf_text(principal.p1_dioptres) +
                          " and " + psf_text(principal.p2_dioptres) + " D at " + psf_text(wavelength_nm) +
                          " nm, needs a grid of " + psf_text(chosen.required_grid_px_exact) + " px over " +
                          psf_text(width_mm) + " mm to sample its phase at the edge of the " +
                          psf_text(geometry.pupil_diameter_mm) + " mm pupil (less than pi per pixel); the largest grid, " +
                          std::to_string(kLargestGridPx) + ", samples at most " +
                          psf_text(max_sampled_defocus_dioptres(wavelength_nm, radius_mm, width_mm / kLargestGridPx)) +
                          " D there, and --grid " + std::to_string(options.grid_px) + " at most " +
                          psf_text(max_sampled_defocus_dioptres(wavelength_nm, radius_mm, width_mm / options.grid_px)) + " D");
  }
}

}  // namespace glarelab::cli
