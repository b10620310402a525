// Depth of field in a session: when it applies, the refusals, and a frame blurred by the depth of
// its scene through the condition's eye (runner/session/condition_depth_of_field.h).
#include "runner/session/condition_depth_of_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "core/errors.h"
#include "core/number_text.h"
#include "glare/refraction/eye_refraction.h"
#include "glare/eye/pupil_model.h"
#include "glare/refraction/spectacle_power.h"
#include "protocols/observer_optics_config.h"
#include "stimuli/display_model.h"
#include "stimuli/frame_depth.h"
#include "stimuli/spectacle_warp.h"

namespace glarelab {
namespace {

SpectacleFrame display_frame(const DisplaySpec& display) {
  return SpectacleFrame{display.width_px, display.height_px, DisplayModel(display).degrees_per_pixel_at_centre()};
}

// Rounded for a label: 1e-3 of a dioptre, a millimetre, a hundredth of a pixel are below anything
// the blur shows.
std::string rounded(double value, double step) { return number_text(std::round(value / step) * step + 0.0); }

SourceLocation where_written(const Experiment& experiment) {
  // "file:line:column" as read_depth_of_field stored it; the file alone otherwise.
  const std::string& text = experiment.observer_optics.depth_of_field_where;
  return SourceLocation{text.empty() ? experiment.source_file : text, 0, 0};
}

}  // namespace

bool depth_of_field_applies(const Experiment& experiment, const std::vector<const LoadedScene*>& shown) {
  if (experiment.observer_optics.depth_of_field) return *experiment.observer_optics.depth_of_field;
  if (!models_observer_optics(experiment)) return false;
  return std::any_of(shown.begin(), shown.end(),
                     [](const LoadedScene* scene) { return scene != nullptr && !scene->image_cd_m2.depth.empty(); });
}

void check_depth_of_field(const Experiment& experiment, const SceneLibrary& scenes) {
  const std::optional<bool> asked = experiment.observer_optics.depth_of_field;
  if (asked == false) return;
  if (asked == true)
    for (const auto& [name, scene] : scenes.scenes())
      if (scene.image_cd_m2.depth.empty())
        throw ConfigError(where_written(experiment), "observer.depth_of_field",
                          "depth_of_field = true blurs each pixel by the depth in its scene's Z channel, but scene '" +
                              name + "' (" + (scene.spec.file.empty() ? "generated" : scene.spec.file) +
                              ") has no Z channel: give every scene a Z channel (metres from the eye), or set "
                              "depth_of_field = false (without the key it applies only to scenes with Z)");
  if (!models_observer_optics(experiment)) return;
  // A point nearer than the spectacle lens' front cannot be seen through it (Eq. 1 has no such
  // vergence at the lens).
  for (const ConditionRow& row : experiment.conditions) {
    const std::optional<ConditionRefraction> refraction = modelled_condition_refraction(experiment, row);
    if (!refraction->traced_lens) continue;
    const double lens_front_m = 1e-3 * refraction->traced_lens->spec().vertex_distance_mm +
                                refraction->traced_lens->centre_thickness_m();
    for (const auto& [name, scene] : scenes.scenes()) {
      if (scene.image_cd_m2.depth.empty()) continue;
      const float nearest_m = *std::min_element(scene.image_cd_m2.depth.begin(), scene.image_cd_m2.depth.end());
      if (nearest_m > lens_front_m) continue;
      throw ConfigError(row.where, "condition '" + row.name() + "' spectacles",
                        "scene '" + name + "' (" + scene.spec.file + ") has a Z of " + number_text(nearest_m) +
                            " m, not beyond the front of [spectacles." + refraction->spectacles + "] (" +
                            rounded(1e3 * lens_front_m, 0.01) + " mm from the cornea): the depth of field cannot "
                            "see it through the lens");
    }
  }
}

FrameEye frame_eye(const ConditionRefraction& refraction, const DisplaySpec& display, double fixation_distance_m) {
  const RefractiveEye eye(refraction.eye);
  const SpectacleFrame frame = display_frame(display);
  // The vergence at the cornea of a point at distance_m along a line of sight: naked, -1 / d; through
  // the lens, the point's vergence at the lens (-1 / (d - h), h the vertex distance) plus the
  // lens' power along that line of sight at the vertex sphere, carried h to the cornea (Eq. 1).
  std::function<std::function<DioptricPower(double)>(double, double)> vergence_along;
  if (refraction.traced_lens) {
    const std::shared_ptr<const SpectacleLens> lens = refraction.traced_lens;
    vergence_along = [lens, frame](double x_px, double y_px) {
      const GazePower power = lens_power_at_gaze(*lens, frame.direction({x_px, y_px}), kFraunhoferD_nm);
      if (!power.through)
        throw std::invalid_argument("runner/session/depth_of_field: the line of sight through pixel (" +
                                    number_text(x_px) + ", " + number_text(y_px) + ") misses the spectacle lens");
      const double vertex_m = 1e-3 * lens->spec().vertex_distance_mm;
      const DioptricPower lens_power = power.vertex_sphere;
      return std::function<DioptricPower(double)>([vertex_m, lens_power](double distance_m) {
        const double at_lens = std::isinf(distance_m) ? 0.0 : -1.0 / (distance_m - vertex_m);
        return effective_power_at_distance(DioptricPower::spherical(at_lens) + lens_power, vertex_m);
      });
    };
  } else {
    vergence_along = [](double, double) {
      return std::function<DioptricPower(double)>(
          [](double distance_m) { return vergence_at_cornea(distance_m, std::nullopt); });
    };
  }
  FrameEye out;
  out.fixation_distance_m = fixation_distance_m;
  const double centre_x = display.width_px / 2, centre_y = display.height_px / 2;
  out.fixation_vergence = vergence_along(centre_x, centre_y)(fixation_distance_m);
  out.accommodation_dioptres = eye.accommodation_dioptres(out.fixation_vergence.mean_dioptres());
  out.residual_at_fixation = eye.residual_error(out.fixation_vergence, out.accommodation_dioptres);
  const double accommodation = out.accommodation_dioptres;
  out.rule = refraction.accommodation;
  // Eq. 13 brings mean(E) to zero for mean(V) from mean(K) - amplitude (the near point) to mean(K)
  // (the far point).
  out.range_far_vergence_dioptres = eye.ocular_refraction().mean_dioptres();
  out.range_near_vergence_dioptres = out.range_far_vergence_dioptres - refraction.eye.accommodation_amplitude_dioptres;
  if (refraction.accommodation == AccommodationRule::range) {
    // Kakimoto's Table 1 order: each point's own Eq. 13 accommodation, so E's mean is zero for every
    // vergence the amplitude reaches, and beyond it E is the defocus from the nearer end.
    out.error = [eye, vergence_along](double x_px, double y_px) {
      const std::function<DioptricPower(double)> vergence = vergence_along(x_px, y_px);
      return EyeErrorAtDistance([eye, vergence](double distance_m) {
        const DioptricPower v = vergence(distance_m);
        return eye.residual_error(v, eye.accommodation_dioptres(v.mean_dioptres()));
      });
    };
    return out;
  }
  out.error = [eye, vergence_along, accommodation](double x_px, double y_px) {
    const std::function<DioptricPower(double)> vergence = vergence_along(x_px, y_px);
    return EyeErrorAtDistance(
        [eye, vergence, accommodation](double distance_m) { return eye.residual_error(vergence(distance_m), accommodation); });
  };
  return out;
}

std::vector<float> seen_depth_m(const ConditionRefraction& refraction, const DisplaySpec& display,
                                const std::vector<float>& composed_depth_m, int threads) {
  if (!refraction.traced_lens) return composed_depth_m;
  // Past the frame's edge the lens shows the display's surroundings: at the display's distance.
  return depth_through_spectacles(composed_depth_m, *refraction.traced_lens, display_frame(display),
                                  display.viewing_distance_mm, static_cast<float>(1e-3 * display.viewing_distance_mm),
                                  threads);
}

FrameDepthOfField depth_of_field_frame(const ConditionRefraction& refraction, const DisplaySpec& display,
                                       const ImageRGBA& seen_cd_m2, const std::vector<float>& depth_m,
                                       double field_cd_m2, int threads) {
  FrameDepthOfField out;
  const std::size_t centre = static_cast<std::size_t>(display.height_px / 2) * static_cast<std::size_t>(display.width_px) +
                             static_cast<std::size_t>(display.width_px / 2);
  out.eye = frame_eye(refraction, display, depth_m.at(centre));
  // Eq. 2 needs a positive luminance; below 1e-4 cd/m2 its tanh has long saturated (7.9 mm).
  out.pupil_diameter_mm = moon_spencer_pupil_diameter_mm(std::max(field_cd_m2, 1e-4));
  DirectionalDepthOfFieldSettings settings;
  settings.degrees_per_pixel = DisplayModel(display).degrees_per_pixel_at_centre();
  settings.pupil_radius_m = 0.5e-3 * out.pupil_diameter_mm;
  settings.residual_error = out.eye.error;
  settings.threads = threads;
  out.image_cd_m2 = apply_directional_depth_of_field(seen_cd_m2, depth_m, settings, &out.report);
  return out;
}

std::string describe_frame_depth_of_field(const FrameDepthOfField& frame) {
  SpheroCylinder residual = frame.eye.residual_at_fixation.prescription();
  // A cylinder that rounds to 0 has no axis (1e-17 D of matrix dust would otherwise name one).
  if (std::abs(residual.cylinder_dioptres) < 5e-4) residual.axis_deg = 0.0;
  const DirectionalDepthOfFieldReport& r = frame.report;
  const std::string accommodated =
      frame.eye.rule == AccommodationRule::range
          ? "accommodated on each depth whose mean vergence at the cornea lies in the range " +
                rounded(frame.eye.range_near_vergence_dioptres, 1e-3) + " to " +
                rounded(frame.eye.range_far_vergence_dioptres, 1e-3) + " D, the centre at "
          : "accommodated " + rounded(frame.eye.accommodation_dioptres, 1e-3) + " D on the centre at ";
  return "depth of field: " + accommodated + rounded(frame.eye.fixation_distance_m, 1e-3) + " m (residual " +
         rounded(residual.sphere_dioptres, 1e-3) + " / " + rounded(residual.cylinder_dioptres, 1e-3) + " x " +
         rounded(residual.axis_deg, 1e-3) + " D), pupil " + rounded(frame.pupil_diameter_mm, 0.01) + " mm, " +
         std::to_string(r.layers) + " layer(s) in " + std::to_string(r.regions_x) + " x " + std::to_string(r.regions_y) +
         " region(s)";
}

}  // namespace glarelab
