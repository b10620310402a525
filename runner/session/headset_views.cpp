#include "runner/session/headset_views.h"

#include <cstdio>
#include <string>
#include <vector>

#include "core/errors.h"
#include "runner/display/openxr_clock.h"
#include "stimuli/display_model.h"

namespace glarelab {

void check_scenes_fit_views(const Experiment& experiment, const SceneLibrary& scenes, const DisplayBackend& display) {
  const auto* source = dynamic_cast<const ViewFieldSource*>(&display);
  if (source == nullptr) return;
  const std::vector<ViewFieldOfView> views = source->view_fields_of_view();
  for (const auto& [name, scene] : scenes.scenes()) {
    // The scene's size as the display model gives it, centred on the line of sight (its smallest
    // angle: a scene placed off-centre subtends less, by the tangent's curvature, and still
    // needs at least this much of the view).
    const double width_deg = DisplayModel(experiment.display).degrees_for_centred_span(scene.image_cd_m2.width_px);
    const double height_deg = DisplayModel(experiment.display).degrees_for_centred_span(scene.image_cd_m2.height_px);
    for (std::size_t view = 0; view < views.size(); ++view) {
      const ViewFieldOfView& fov = views[view];
      if (width_deg <= fov.width_deg() && height_deg <= fov.height_deg()) continue;
      char text[512];
      std::snprintf(text, sizeof text,
                    "scene '%s' (%d x %d px) subtends %.1f x %.1f deg by the display model ([display] pixel_pitch_mm "
                    "%g at viewing_distance_mm %g): more than the headset's %s view shows, %.1f x %.1f deg (its field "
                    "of view from the OpenXR runtime); give the display model the view's degrees (docs/STEREO.md)",
                    name.c_str(), scene.image_cd_m2.width_px, scene.image_cd_m2.height_px, width_deg, height_deg,
                    experiment.display.pixel_pitch_mm, experiment.display.viewing_distance_mm,
                    view == 0 ? "left eye's" : "right eye's", fov.width_deg(), fov.height_deg());
      throw ConfigError(scene.spec.where, "scenes." + name, text);
    }
  }
}

}  // namespace glarelab
