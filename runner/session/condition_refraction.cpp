// Each condition's refraction at the display, and the refusals a session makes for it before
// anything is written (runner/session/condition_refraction.h).
#include "runner/session/condition_refraction.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "core/number_text.h"
#include "glare/refraction/astigmatic_phase.h"
#include "glare/wave/chromatic_psf.h"
#include "glare/wave/cie_cmf.h"
#include "glare/eye/eye_parameters.h"
#include "glare/wave/fresnel.h"
#include "glare/wave/psf.h"
#include "stimuli/display_model.h"
#include "stimuli/spectacle_warp.h"
#include "protocols/glare_config.h"
#include "protocols/observer_optics_config.h"

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// The glare's modes in a condition: one, or one per side (forced choice's glare_a, glare_b).
bool shows_glare(const Experiment& experiment, const ConditionRow& row) {
  const auto sides = position_glare_modes(row);
  return sides ? (sides->first != GlareMode::control || sides->second != GlareMode::control)
               : glare_mode_for(experiment.glare, row) != GlareMode::control;
}

// Shortest round-trip text of a value rounded to 1e-6 (the residual's matrix arithmetic leaves
// 1e-16 dust on a sphere that is exactly 0).
std::string rounded(double value) {
  const double r = std::round(value * 1e6) / 1e6;
  return number_text(r == 0.0 ? 0.0 : r);
}

}  // namespace

bool models_observer_optics(const Experiment& experiment) {
  if (experiment.observer_optics.refraction_stated) return true;
  if (experiment.observer_optics.depth_of_field == true) return true;
  for (const ConditionRow& row : experiment.conditions)
    if (spectacles_for(experiment.observer_optics, row) != nullptr) return true;
  return false;
}

std::optional<ConditionRefraction> condition_refraction(const Experiment& experiment, const ConditionRow& row) {
  if (!models_observer_optics(experiment)) return std::nullopt;
  return modelled_condition_refraction(experiment, row);
}

ConditionRefraction modelled_condition_refraction(const Experiment& experiment, const ConditionRow& row) {
  const ObserverOptics& optics = experiment.observer_optics;
  ConditionRefraction out;
  out.condition = row.name();
  EyeRefraction eye;
  if (optics.refraction_stated) {
    eye.correcting_prescription = optics.refraction.prescription;
    eye.prescription_vertex_distance_m = 1e-3 * optics.refraction.vertex_distance_mm;
  }
  // Kakimoto's Table 2 amplitude (11.93 D) is a young eye's; an experiment names its observer's age,
  // so the amplitude is the table's when it gives one, else Hofstetter's for that age.
  if (optics.refraction_stated && optics.refraction.accommodation_amplitude_dioptres >= 0.0) {
    eye.accommodation_amplitude_dioptres = optics.refraction.accommodation_amplitude_dioptres;
    out.amplitude_source = "[observer.refraction] accommodation_amplitude_dioptres";
  } else {
    const double age_years = experiment.glare.observer_eye.age_years;
    eye.accommodation_amplitude_dioptres = hofstetter_amplitude_dioptres(age_years);
    out.amplitude_source = "Hofstetter 18.5 - 0.3 x [observer] age_years " + number_text(age_years);
  }
  out.accommodation_amplitude_dioptres = eye.accommodation_amplitude_dioptres;
  out.eye = eye;
  out.accommodation = optics.accommodation;
  if (const SpectaclesSettings* pair = spectacles_for(optics, row)) {
    out.spectacles = pair->name;
    out.lens = ThinSpectacleLens{pair->prescription, 1e-3 * pair->vertex_distance_mm};
    SpectacleLensSpec spec;
    spec.prescription = pair->prescription;
    spec.refractive_index_d = pair->refractive_index;
    spec.abbe_number_d = pair->abbe_number;
    spec.vertex_distance_mm = pair->vertex_distance_mm;
    spec.decentration_mm = glm::dvec2(pair->decentration_x_mm, pair->decentration_y_mm);
    spec.near_add_dioptres = pair->near_add_dioptres;
    try {
      out.traced_lens = std::make_shared<const SpectacleLens>(spec);
      out.warp_grids = std::make_shared<SpectacleWarpGridCache>(out.traced_lens);
    } catch (const std::invalid_argument& error) {
      throw ConfigError(row.where, "condition '" + row.name() + "' spectacles",
                        "[spectacles." + pair->name + "] cannot be made as a lens: " + error.what());
    }
  }
  out.viewing_distance_m = 1e-3 * experiment.display.viewing_distance_mm;
  const RefractiveEye refractive_eye(eye);
  out.ocular_refraction = refractive_eye.ocular_refraction();
  ViewingCondition viewing;
  viewing.fixation_distance_m = out.viewing_distance_m;
  viewing.spectacles = out.lens;
  try {
    out.fixation = refraction_at_fixation(refractive_eye, viewing);
  } catch (const std::invalid_argument& error) {
    throw ConfigError(row.where, "condition '" + row.name() + "' spectacles",
                      "the display at [display] viewing_distance_mm " + number_text(experiment.display.viewing_distance_mm) +
                          " cannot be seen through '" + out.spectacles + "': " + error.what());
  }
  return out;
}

namespace {

SpectacleFrame display_frame(const DisplaySpec& display) {
  return SpectacleFrame{display.width_px, display.height_px, DisplayModel(display).degrees_per_pixel_at_centre()};
}

}  // namespace

ImageRGBA frame_through_spectacles(const ConditionRefraction& refraction, const DisplaySpec& display,
                                   const ImageRGBA& composed_cd_m2, int threads) {
  if (!refraction.traced_lens) return composed_cd_m2;
  SpectacleWarpOptions options;
  options.scene_distance_mm = display.viewing_distance_mm;  // the display is the scene, at its distance
  options.threads = threads;
  const SpectacleFrame frame = display_frame(display);
  if (!refraction.warp_grids) return warp_through_spectacles(composed_cd_m2, *refraction.traced_lens, frame, options);
  return warp_through_spectacles(composed_cd_m2, *refraction.warp_grids->grids(frame, options), options);
}

std::vector<ConditionRefraction> condition_refractions(const Experiment& experiment) {
  std::vector<ConditionRefraction> all;
  if (!models_observer_optics(experiment)) return all;
  all.reserve(experiment.conditions.size());
  for (const ConditionRow& row : experiment.conditions) all.push_back(modelled_condition_refraction(experiment, row));
  return all;
}

double largest_session_pupil_diameter_mm(const GlareSpec& spec) { return spec.eye.pupil_max_diameter_mm; }

void check_condition_refractions(const Experiment& experiment) {
  if (!models_observer_optics(experiment)) return;
  const GlareSpec& spec = experiment.glare;
  const double pupil_mm = largest_session_pupil_diameter_mm(spec);
  const double radius_mm = 0.5 * pupil_mm, width_mm = spec.aperture_width_mm;
  const double pixel_mm = width_mm / spec.grid_px;
  ChromaticPsfOptions chromatic;
  chromatic.reference_wavelength_nm = kReferenceWavelengthNm;
  for (const ConditionRow& row : experiment.conditions) {
    // The optics are modelled (checked above), so every condition has its refraction.
    const ConditionRefraction refraction = modelled_condition_refraction(experiment, row);
    if (refraction.traced_lens) {
      // Every line of sight to the display must pass through the lens (the 3 x 3 grid's corners are
      // the display's corner pixels, the widest angles).
      try {
        trace_grid_vertices(*refraction.traced_lens, display_frame(experiment.display), kFraunhoferD_nm, 3,
                            experiment.display.viewing_distance_mm);
      } catch (const std::invalid_argument& error) {
        throw ConfigError(row.where, "condition '" + row.name() + "' spectacles", "the display is not seen through all of [spectacles." +
                                                                                      refraction.spectacles + "]: " + error.what());
      }
    }
    if (!shows_glare(experiment, row)) continue;
    const GlareModel model = glare_model_for(spec, row);
    // Luidolt's kernel has a pupil, but its only phase is Eq. 5.6's fixed Fresnel term: no defocus.
    if (model == GlareModel::spencer || model == GlareModel::cie || model == GlareModel::luidolt)
      throw ConfigError(row.where, "condition '" + row.name() + "' glare_model",
                        "the observer's refraction ([observer.refraction] or spectacles) blurs the wave-optics PSF, "
                        "but glare_model '" + to_string(model) +
                            (model == GlareModel::luidolt ? "' has no defocus phase to carry it" : "' has no pupil to carry it") +
                            ": use \"human\", \"ritschel\" or \"hybrid\" for this condition, or leave "
                            "the refraction and spectacles out of the experiment");
    // Every wavelength of the spectral PSF carries its own error (the LCA, glare/wave/chromatic_psf.h);
    // the message names the one that needs the finest grid.
    std::optional<std::pair<SpectralSample, PhaseSamplingReport>> worst;
    DioptricPower worst_error;
    for (const SpectralSample& sample : spectral_samples(spec.wavelength_samples)) {
      const DioptricPower error = chromatic_power_error(refraction.fixation.residual, sample.wavelength_nm, chromatic);
      const PhaseSamplingReport report =
          check_power_error_sampling(error, sample.wavelength_nm, radius_mm, pixel_mm, width_mm);
      if (report.aliased && (!worst || report.required_grid_px_exact > worst->second.required_grid_px_exact)) {
        worst = std::pair{sample, report};
        worst_error = error;
      }
    }
    if (!worst) continue;
    const double wavelength_nm = worst->first.wavelength_nm;
    const PrincipalPowers principal = principal_powers(worst_error);
    const SpheroCylinder residual = refraction.fixation.residual.prescription();
    throw ConfigError(
        {experiment.source_file, 0, 0}, "glare.grid_px",
        "condition '" + row.name() + "' (spectacles '" + refraction.spectacles + "'): the residual refraction error at " +
            "the display, " + rounded(residual.sphere_dioptres) + " / " + rounded(residual.cylinder_dioptres) + " x " +
            rounded(residual.axis_deg) + " D (principal powers " + rounded(principal.p1_dioptres) + " and " +
            rounded(principal.p2_dioptres) + " D at " + number_text(wavelength_nm) +
            " nm with the eye's chromatic aberration), needs grid_px of at least " +
            number_text(std::ceil(worst->second.required_grid_px_exact)) + " over aperture_width_mm " +
            number_text(width_mm) + " to sample its pupil phase at the edge of the eye's largest pupil (" +
            number_text(pupil_mm) + " mm; less than pi per sample); grid_px " + std::to_string(spec.grid_px) +
            " samples at most " + rounded(max_sampled_defocus_dioptres(wavelength_nm, radius_mm, pixel_mm)) +
            " D there. Raise [glare] grid_px, or give the condition spectacles that correct the observer");
  }
}

std::string describe_condition_refraction(const ConditionRefraction& r) {
  const SpheroCylinder residual = r.fixation.residual.prescription();
  const SpheroCylinder ocular = r.ocular_refraction.prescription();
  // A 4 mm pupil, the usual photopic one, for a figure comparable across conditions (the frame's
  // pupil follows the eye model).
  const BlurEllipse blur = geometric_blur_ellipse(r.fixation.residual, 0.5e-3 * 4.0);
  std::string text = "condition '" + r.condition + "': spectacles '" + r.spectacles + "'";
  if (r.lens)
    text += " (" + rounded(r.lens->prescription.sphere_dioptres) + " / " + rounded(r.lens->prescription.cylinder_dioptres) +
            " x " + rounded(r.lens->prescription.axis_deg) + " at " + rounded(1e3 * r.lens->vertex_distance_m) + " mm)";
  text += "; ocular refraction " + rounded(ocular.sphere_dioptres) + " / " + rounded(ocular.cylinder_dioptres) + " x " +
          rounded(ocular.axis_deg) + " D; accommodation amplitude " + rounded(r.accommodation_amplitude_dioptres) + " D (" +
          r.amplitude_source + "); display at " + rounded(r.viewing_distance_m) + " m: accommodation " +
          rounded(r.fixation.accommodation_dioptres) + " D, residual sphere " + rounded(residual.sphere_dioptres) +
          " D, cylinder " + rounded(residual.cylinder_dioptres) + " D, axis " + rounded(residual.axis_deg) +
          " deg (TABO); geometric blur through a 4 mm pupil " + rounded(2.0 * kDegPerRad * blur.semi_major_rad) + " x " +
          rounded(2.0 * kDegPerRad * blur.semi_minor_rad) + " deg across";
  return text;
}

}  // namespace glarelab
