#include "runner/session/headset_views.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/number_text.h"
#include "protocols/stated_keys.h"
#include "runner/display/openxr_clock.h"
#include "stimuli/display_model.h"

namespace glarelab {
namespace {

constexpr double kRadiansPerDegree = 0.017453292519943295769;
// How far a stated pitch, or a view's pixels' height from their width, may lie (relative): the
// views' angles come as floats, and a file states a pitch to a few digits.
constexpr double kPitchTolerance = 0.01;

std::string fixed(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

const char* eye_name(std::size_t view) { return view == 0 ? "left eye's" : "right eye's"; }

}  // namespace

ViewPixelPitch view_pixel_pitch(const ViewFieldOfView& view, int view_width_px, int view_height_px,
                                double viewing_distance_mm) {
  const double across = std::tan(view.right_deg * kRadiansPerDegree) - std::tan(view.left_deg * kRadiansPerDegree);
  const double high = std::tan(view.up_deg * kRadiansPerDegree) - std::tan(view.down_deg * kRadiansPerDegree);
  return {viewing_distance_mm * across / view_width_px, viewing_distance_mm * high / view_height_px};
}

std::optional<HeadsetDisplayModel> headset_display_model(const Experiment& experiment, const DisplayBackend& display) {
  const auto* source = dynamic_cast<const ViewFieldSource*>(&display);
  if (source == nullptr) return std::nullopt;
  const std::vector<ViewFieldOfView> views = source->view_fields_of_view();
  if (views.empty()) return std::nullopt;
  const DisplaySpec& spec = experiment.display;
  const int view_width_px = spec.width_px / 2;
  const int view_height_px = spec.height_px;
  const double distance_mm = spec.viewing_distance_mm;
  const ViewPixelPitch left = view_pixel_pitch(views[0], view_width_px, view_height_px, distance_mm);
  const StatedKey stated_pitch = stated_key(experiment.source_file, "display", "pixel_pitch_mm");
  const StatedKey stated_height = stated_key(experiment.source_file, "display", "height_px");
  const SourceLocation height_where = stated_height.value.value_or(stated_height.table);
  HeadsetDisplayModel model;
  model.pixel_pitch_mm = left.across_mm;
  model.derived = !stated_pitch.value.has_value();
  const std::string views_text = std::to_string(view_width_px) + " x " + std::to_string(view_height_px) +
                                 " px across the " + eye_name(0) + " view's " + fixed(views[0].width_deg(), 1) + " x " +
                                 fixed(views[0].height_deg(), 1) + " deg";
  if (stated_pitch.value && std::abs(spec.pixel_pitch_mm - model.pixel_pitch_mm) > kPitchTolerance * model.pixel_pitch_mm)
    throw ConfigError(*stated_pitch.value, "display.pixel_pitch_mm",
                      number_text(spec.pixel_pitch_mm) + " mm contradicts the headset's views: " + views_text +
                          " make a pixel " + fixed(model.pixel_pitch_mm, 4) + " mm at viewing_distance_mm " +
                          number_text(distance_mm) + " (its field of view from the OpenXR runtime); state that, or "
                          "leave pixel_pitch_mm out and the views give it (docs/STEREO.md)");
  for (std::size_t view = 0; view < views.size(); ++view) {
    const ViewPixelPitch pitch = view_pixel_pitch(views[view], view_width_px, view_height_px, distance_mm);
    if (std::abs(pitch.high_mm - model.pixel_pitch_mm) > kPitchTolerance * model.pixel_pitch_mm) {
      const double square_height_px = pitch.high_mm * view_height_px / model.pixel_pitch_mm;
      throw ConfigError(height_where, "display.height_px",
                        "the headset's " + std::string(eye_name(view)) + " view is " +
                            fixed(views[view].width_deg(), 1) + " x " + fixed(views[view].height_deg(), 1) +
                            " deg: with halves of " + std::to_string(view_width_px) + " x " +
                            std::to_string(view_height_px) + " px its pixels are " + fixed(model.pixel_pitch_mm, 4) +
                            " mm across and " + fixed(pitch.high_mm, 4) + " mm high, and every scene would be "
                            "stretched; height_px = " + std::to_string(std::lround(square_height_px)) +
                            " makes them square (docs/STEREO.md)");
    }
    if (std::abs(pitch.across_mm - model.pixel_pitch_mm) > kPitchTolerance * model.pixel_pitch_mm)
      throw ConfigError(stated_key(experiment.source_file, "display", "width_px").value.value_or(stated_height.table),
                        "display.width_px",
                        "the headset's views differ: the " + std::string(eye_name(view)) + " makes a pixel " +
                            fixed(pitch.across_mm, 4) + " mm across, the left eye's " +
                            fixed(model.pixel_pitch_mm, 4) + " mm; one display model cannot show both");
  }
  const double pitch_mm = model.derived ? model.pixel_pitch_mm : spec.pixel_pitch_mm;
  DisplaySpec shown = spec;
  shown.pixel_pitch_mm = pitch_mm;
  model.description = "from the headset's views: " + views_text + " make a pixel " + fixed(model.pixel_pitch_mm, 4) +
                      " mm at viewing_distance_mm " + number_text(distance_mm) + " (" +
                      fixed(DisplayModel(shown).degrees_per_pixel_at_centre(), 4) + " deg a pixel at the centre); " +
                      (model.derived ? "pixel_pitch_mm not stated: the session takes " + fixed(pitch_mm, 4) + " mm"
                                     : "the file's pixel_pitch_mm " + number_text(pitch_mm) + " mm agrees within 1 %");
  return model;
}

void check_headset_experiment(const Experiment& experiment, const std::string& display, bool display_chosen) {
  if (display != "openxr") return;
  const bool file_chose = !display_chosen && !experiment.display_output.empty();
  const SourceLocation where = file_chose ? experiment.display_output_where : SourceLocation{"--display", 0, 0};
  const std::string key = file_chose ? "display.output" : "display";
  if (experiment.display.stereo != StereoMode::side_by_side)
    throw ConfigError(where, key,
                      "openxr shows each eye its half of a side-by-side frame: the experiment needs [display] stereo = "
                      "\"side_by_side\" (docs/STEREO.md)");
  if (experiment.display.fullscreen)
    throw ConfigError(where, key,
                      "openxr shows the frames in the headset, with a mirror window for the keyboard: [display] "
                      "fullscreen = true is for --display window (docs/STEREO.md)");
}

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
